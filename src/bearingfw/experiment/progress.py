"""The progress display of a run: cells done of total, the last cell, elapsed time and an ETA; then
each figure as it is drawn (during the cells, a record and intensity's figures are drawn as soon
as its cells are done).

One line on stderr, rewritten in place on a terminal (a new line per cell otherwise, so that logs
stay readable). The ETA weighs what is left by model: cells of one model cost about the same
(the same laws, the same record length), while models can differ a lot (a smooth hysteretic law's
cell may take a hundred times an elastic one's); a model with no finished cell yet counts at the mean of all
finished cells. The remaining work is shared by the workers.
"""

from __future__ import annotations

import sys
import threading
import time
from collections import Counter, defaultdict
from collections.abc import Mapping, Sequence
from typing import TextIO

from bearingfw.experiment.execute import CellSummary

__all__ = ["Progress", "estimate_remaining", "format_duration"]


def format_duration(seconds: float) -> str:
    """``"1:02:03"``, ``"4:05"`` or ``"7 s"``."""
    seconds = max(0.0, seconds)
    if seconds < 60:
        return f"{seconds:.0f} s"
    minutes, secs = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def estimate_remaining(
    times: Mapping[str, Sequence[float]], remaining: Mapping[str, int], workers: int
) -> float | None:
    """Seconds of wall time left: per-model mean cell time x cells left, over ``workers`` (None: no data)."""
    finished = [t for per_model in times.values() for t in per_model]
    if not finished:
        return None
    overall = sum(finished) / len(finished)
    work = sum(n * (sum(times[m]) / len(times[m]) if times.get(m) else overall) for m, n in remaining.items())
    return work / max(1, min(workers, sum(remaining.values()) or 1))


class Progress:
    """Prints the run's progress to ``stream`` (default stderr); ``quiet`` prints nothing."""

    def __init__(self, stream: TextIO | None = None, quiet: bool = False):
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.live = getattr(self.stream, "isatty", lambda: False)()
        self.times: dict[str, list[float]] = defaultdict(list)
        self.remaining: Counter = Counter()
        self.done = self.total = self.failed = 0
        self.workers = 1
        self.start = time.perf_counter()
        self.open = False  # a live line is on screen without its newline
        self.figures = 0  # figures drawn so far
        self.figure_time = 0.0
        self._lock = threading.Lock()  # figures are reported from a drawing thread

    def _print(self, text: str, rewrite: bool = False) -> None:
        """Print a line; ``rewrite``: on a terminal, in place of the previous such line, and left open."""
        if self.quiet:
            return
        with self._lock:
            if rewrite and self.live:
                print("\r\033[K" + text[:200], end="", file=self.stream, flush=True)
                self.open = True
                return
            print(("\r\033[K" if self.open else "") + text, file=self.stream, flush=True)
            self.open = False

    def begin(self, models: Sequence[str], skipped: int, executor: str, workers: int, thinned: int = 0) -> None:
        """``models``: the model of every cell to run; ``skipped``: cells already finished (``thinned``
        of them with their histories cut to a coarser ``[output] every``)."""
        self.remaining = Counter(models)
        self.total = len(models)
        self.workers = workers
        self.start = time.perf_counter()
        note = f"; {skipped} finished cell(s) kept" if skipped else ""
        if thinned:
            note += f" ({thinned} with their histories thinned to the new [output] every)"
        if self.total:
            self._print(f"running {self.total} cell(s) on {executor} ({workers} worker(s)){note}")
        else:
            self._print(f"nothing to run: all {skipped} cell(s) finished earlier with the same inputs")

    def cell(self, summary: CellSummary) -> None:
        self.done += 1
        self.remaining[summary.model] -= 1
        self.times[summary.model].append(summary.wall_time)
        self.failed += summary.status != "ok"
        elapsed = time.perf_counter() - self.start
        eta = estimate_remaining(self.times, +self.remaining, self.workers)
        state = "ok" if summary.status == "ok" else f"{summary.status.upper()}: {summary.error}"
        line = (f"[{self.done}/{self.total}] {summary.id} {state} ({summary.wall_time:.1f} s) | elapsed "
                f"{format_duration(elapsed)}" + ("" if eta is None or self.done == self.total else
                                                 f" | ETA {format_duration(eta)}"))
        self._print(line, rewrite=summary.status == "ok" and self.done < self.total)

    def figure(self, stem: str, seconds: float) -> None:
        """Figure ``stem`` was drawn, in ``seconds``."""
        with self._lock:
            self.figures += 1
            self.figure_time += seconds
            count = self.figures
        cells = f" | cells {self.done}/{self.total}" if self.done < self.total else ""
        self._print(f"[figure {count}] {stem} ({seconds:.1f} s){cells} | elapsed "
                    f"{format_duration(time.perf_counter() - self.start)}", rewrite=True)

    def note(self, message: str) -> None:
        """A line about the run's later steps (after the cells)."""
        self._print(message)

    def finish(self, message: str) -> None:
        self._print(message)
