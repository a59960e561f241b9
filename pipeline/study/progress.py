"""A text progress bar on stderr, for a study's tasks or a single long simulation."""

import math
import sys
import time


class Progress:
    """A text progress bar on stderr: work done, elapsed time and ETA (a line every 5 s when not a terminal).

    ``unit`` names what is counted (finished tasks; seconds of motion for a single long run).
    The clock counts from the bar's creation, so that what comes before the first result
    (starting a cluster) is counted; the ETA counts from :meth:`restart` (the computing alone).
    On a terminal :meth:`tick` keeps the clock running while nothing finishes, with what the
    run waits for (:attr:`status`), and :meth:`note` prints a line of its own above the bar.
    """

    def __init__(self, total, done=0, stream=None, enabled=True, width=30, unit="tasks"):
        self.total, self.done, self.width, self.unit = total, done, width, unit
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.start = time.monotonic()
        self.computing = self.start  # the ETA's clock
        self.first = done
        self.status = ""
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.last_line = -1.0
        self.drawn = 0  # characters of the bar on the terminal's line
        self.show()

    def advance(self, n=1):
        self.done += n
        self.show()

    def update(self, done):
        """Set the work done so far (a run that reports its own progress)."""
        self.done = done
        self.show()

    def restart(self):
        """The computing starts now (the cluster is ready): the ETA counts from here, the clock goes on."""
        self.computing = time.monotonic()
        self.first = self.done
        self.last_line = -1.0

    def tick(self, status=None):
        """Redraw the bar on a terminal (at most once a second) so that its clock runs while nothing finishes.

        Parameters
        ----------
        status : str, optional
            What the run waits for ("starting 2 workers"), shown after the clock; "" clears it.
        """
        changed = status is not None and status != self.status
        if changed:
            self.status = status
        if not self.enabled:
            return
        if self.tty:
            if changed or time.monotonic() - self.start - self.last_line >= 1.0:
                self._draw()
        elif changed and status:  # in logs: a line when the run starts waiting for something
            self._draw()

    def note(self, text):
        """Print ``text`` on a line of its own (a notice), above the bar, whether the bar is shown or not."""
        if self.enabled and self.tty and self.drawn:
            self.stream.write("\r" + " " * self.drawn + "\r")
        self.stream.write(text + "\n")
        if self.enabled and self.tty and self.drawn:
            self._draw()
        self.stream.flush()

    def end(self):
        """End the bar's line on a terminal: the run stops before its last task, and says why on the next line."""
        if self.enabled and self.tty and self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = 0

    def show(self, final=False):
        if not self.enabled or (final and getattr(self, "shown_total", False)):
            return
        elapsed = time.monotonic() - self.start
        if not self.tty and not final and self.done not in (self.first, self.total) \
                and elapsed - self.last_line < 5.0:
            return  # in logs: a line every 5 s at most
        self._draw()

    def _draw(self):
        now = time.monotonic()
        elapsed = now - self.start
        self.last_line = elapsed
        frac = self.done / self.total if self.total else 1.0
        new = self.done - self.first
        eta = (now - self.computing) / new * (self.total - self.done) if new else math.nan
        bar = "#" * int(round(frac * self.width))
        text = (f"[{bar:<{self.width}}] {self.done:g}/{self.total:g} {self.unit} {100 * frac:5.1f}% "
                f"elapsed {elapsed:6.1f} s" + (f" eta {eta:6.1f} s" if math.isfinite(eta) else "")
                + (f" ({self.status})" if self.status and self.done < self.total else ""))
        if self.tty:
            self.stream.write("\r" + text + " " * max(0, self.drawn - len(text)))
            self.drawn = len(text)
            if self.done == self.total:
                self.stream.write("\n")
                self.drawn = 0
        else:
            self.stream.write(text + "\n")
        self.stream.flush()
        self.shown_total = self.done == self.total
