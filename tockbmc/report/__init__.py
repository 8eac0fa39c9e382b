"""Presenting results: diagnostics, model structure, and (later) traces."""
