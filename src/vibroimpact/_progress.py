"""Progress of long library calls: a tqdm bar when run interactively, and milestones in the log.

Every long call (sweeps, transitions, basins, regime maps, continuation, bifurcation curves, the
benchmarks) takes ``progress=None | True | False``.  ``None`` (the default) shows a bar only where
someone watches: standard error is a terminal and the call does not run inside a Snakemake job.
Whatever the bar does, the call logs its start, every tenth of the way and its end to the
``vibroimpact`` logger at INFO level (a Snakemake rule's script sends that to the rule's log).
"""

from __future__ import annotations

import logging
import sys
import time

log = logging.getLogger("vibroimpact")


def interactive() -> bool:
    """Whether progress bars are drawn: standard error is a terminal and the caller is not a Snakemake job."""
    return bool(getattr(sys.stderr, "isatty", lambda: False)()) and "snakemake" not in sys.modules


class Progress:
    """Count work done out of ``total`` (None when unknown); a context manager."""

    def __init__(self, total, desc: str, enabled: bool | None = None, unit: str = "it"):
        self.total, self.desc, self.n = total, desc, 0
        self._tenth = 1  # the next tenth of the way to log
        self._start = time.perf_counter()
        self._bar = None
        if enabled is None:
            enabled = interactive()
        if enabled:
            try:
                from tqdm.auto import tqdm
            except ImportError:  # the bar is optional; the log is not
                tqdm = None
            if tqdm is not None:
                self._bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False)
        log.info("%s: started (%s %s)", desc, "?" if total is None else total, unit)

    def update(self, k: int = 1) -> None:
        self.n += k
        if self._bar is not None:
            self._bar.update(k)
        if self.total and 10 * self.n >= self._tenth * self.total:
            log.info("%s: %d/%d (%.0f s)", self.desc, self.n, self.total, time.perf_counter() - self._start)
            while self._tenth * self.total <= 10 * self.n:
                self._tenth += 1

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        log.info("%s: done, %d in %.1f s", self.desc, self.n, time.perf_counter() - self._start)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
