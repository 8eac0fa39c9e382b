"""Properties: each assertion as goals over the transition system, and CSP specifications as monitors."""
