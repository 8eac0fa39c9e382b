"""bmc layer: built in a later issue; see DEVELOPERS.md."""
