"""Engines: every solver loop (BMC with k-induction, trace inclusion) and the witnesses they decode."""
