"""A text progress bar on stderr, for a study's tasks or a single long simulation."""

import math
import sys
import time


class Progress:
    """A text progress bar on stderr: work done, elapsed time and ETA (a line every 5 s when not a terminal).

    ``unit`` names what is counted (finished tasks; seconds of motion for a single long run).
    """

    def __init__(self, total, done=0, stream=None, enabled=True, width=30, unit="tasks"):
        self.total, self.done, self.width, self.unit = total, done, width, unit
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.start = time.monotonic()
        self.first = done
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.last_line = -1.0
        self.show()

    def advance(self, n=1):
        self.done += n
        self.show()

    def update(self, done):
        """Set the work done so far (a run that reports its own progress)."""
        self.done = done
        self.show()

    def restart(self):
        """Start the clock again (the cluster is ready): elapsed and ETA count only computing."""
        self.start = time.monotonic()
        self.first = self.done
        self.last_line = -1.0

    def show(self, final=False):
        if not self.enabled or (final and getattr(self, "shown_total", False)):
            return
        elapsed = time.monotonic() - self.start
        frac = self.done / self.total if self.total else 1.0
        if not self.tty and not final and self.done not in (self.first, self.total) \
                and elapsed - self.last_line < 5.0:
            return  # in logs: a line every 5 s at most
        self.last_line = elapsed
        new = self.done - self.first
        eta = elapsed / new * (self.total - self.done) if new else math.nan
        bar = "#" * int(round(frac * self.width))
        text = (f"[{bar:<{self.width}}] {self.done:g}/{self.total:g} {self.unit} {100 * frac:5.1f}% "
                f"elapsed {elapsed:6.1f} s" + (f" eta {eta:6.1f} s" if math.isfinite(eta) else ""))
        self.stream.write(("\r" + text) if self.tty else text + "\n")
        if self.tty and self.done == self.total:
            self.stream.write("\n")
        self.stream.flush()
        self.shown_total = self.done == self.total
