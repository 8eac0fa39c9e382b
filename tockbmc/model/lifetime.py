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


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return False
    except (OSError, IndexError):  # no /proc here: whether a process of that number exists
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:  # another user's process has the number now: the owner is gone
            return False
        return True
    return state not in ("Z", "X")


def end_with(owner: int | None = None) -> None:
    """End this process (at once, without clean-up) when `owner` ends: its parent when None."""
    if owner is None:
        parent = os.getppid()

        def gone() -> bool:
            return os.getppid() != parent
    else:
        def gone() -> bool:
            return not _alive(owner)

    def watch() -> None:
        while not gone():
            time.sleep(POLL)
        os._exit(0)

    threading.Thread(target=watch, name="tockbmc-orphaned", daemon=True).start()
