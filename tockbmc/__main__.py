"""`python -m tockbmc`: the `tockbmc` command."""

from tockbmc.launch import main

main()
