"""The `tockbmc` command's entry point: Ctrl-C or SIGTERM while tockbmc is still being imported
ends it as it ends a check (exit 130 or 143, one line), not with a Python traceback.

Importing the checker (Z3, Lark, rich and tockbmc's own modules) takes a few tenths of a second,
before `cli.main` can take signals over; this module imports nothing of tockbmc's until its
handlers are in place, and the package's `__init__` imports lazily for the same reason.
"""

from __future__ import annotations

import os
import signal
import time
from types import FrameType

HOLD_IMPORT = "TOCKBMC_HOLD_IMPORT"  # tests: a file to create, then wait for a signal, before importing


def _stop(signum: int, _frame: FrameType | None) -> None:
    os.write(2, b"tockbmc: interrupted\n" if signum == signal.SIGINT else b"tockbmc: terminated (SIGTERM)\n")
    os._exit(128 + signum)


def main() -> None:
    """Console entry point: `cli.main`, imported under handlers that end tockbmc at once."""
    # A signal tockbmc was started ignoring (`cmd &` in a script ignores Ctrl-C) stays ignored.
    previous = {s: signal.signal(s, _stop) for s in (signal.SIGINT, signal.SIGTERM)
                if signal.getsignal(s) is not signal.SIG_IGN}
    hold = os.environ.get(HOLD_IMPORT)
    if hold:
        with open(hold, "w"):
            pass
        while True:  # the test's signal ends tockbmc here, as it would during the import
            time.sleep(0.05)
    from tockbmc.cli import main as cli_main

    for s, handler in previous.items():
        signal.signal(s, handler)
    cli_main()


if __name__ == "__main__":
    main()
