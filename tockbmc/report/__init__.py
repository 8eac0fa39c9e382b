"""Report: printers of results, diagnostics and the model's structure (they never solve)."""
