"""A helper process's lifetime: it ends when the tockbmc process it works for ends, however that
ends (Ctrl-C, SIGTERM, killed outright, out of memory), within a fraction of a second.

Every process tockbmc starts (a worker, an engine of the portfolio, a Spacer query) watches its
owner from a daemon thread. A process whose owner is its parent sees its parent id change when the
owner ends (the kernel hands it on at once); a worker started by the fork server looks the owner up:
gone, or a zombie its own parent has not reaped yet (a zombie still answers `kill(pid, 0)`).
"""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

POLL = 0.2  # seconds between looks


def _started(pid: int) -> str | None:
    """When process `pid` started (clock ticks since boot: `/proc`'s field 22), None if it is gone or
    a zombie; "" where there is no `/proc` (then whether a process of that number exists)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except FileNotFoundError:
        return None
    except (OSError, IndexError):
        try:
            os.kill(pid, 0)
        except (ProcessLookupError, PermissionError):  # PermissionError: another user's process has the number
            return None
        return ""
    return None if fields[0] in ("Z", "X") else fields[19]


def end_with(owner: int | None = None) -> None:
    """End this process (at once, without clean-up) when `owner` ends: its parent when None."""
    if owner is None:
        parent = os.getppid()

        def gone() -> bool:
            return os.getppid() != parent
    else:
        started = _started(owner)  # a later process given the same number is not the owner

        def gone() -> bool:
            return started is None or _started(owner) != started

    def watch() -> None:
        while not gone():
            time.sleep(POLL)
        os._exit(0)

    threading.Thread(target=watch, name="tockbmc-orphaned", daemon=True).start()
