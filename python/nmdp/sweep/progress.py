"""The sweep's progress on stderr: runs done of the total, failures, elapsed time and an estimate of
the time left. On a terminal one line redrawn in place (at most 10 times a second); to a file or a
pipe one line per tenth of the runs, so a log stays short; nothing when quiet.
"""
import sys
import time


def _clock(seconds):
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"


class Progress:
    WIDTH = 30  # characters of the bar

    def __init__(self, total, stream=None, quiet=False):
        self.total, self.done, self.failed = total, 0, 0
        self.stream = stream or sys.stderr
        self.quiet = quiet or total == 0
        self.tty = not self.quiet and self.stream.isatty()
        self.start = time.monotonic()
        self._drawn = 0.0
        self._tenths = 0
        if self.tty:
            self._draw()

    def line(self):
        elapsed = time.monotonic() - self.start
        eta = f", ETA {_clock(elapsed / self.done * (self.total - self.done))}" if 0 < self.done < self.total else ""
        failed = f", {self.failed} failed" if self.failed else ""
        return f"{self.done}/{self.total} runs{failed}, {_clock(elapsed)} elapsed{eta}"

    def _draw(self):
        filled = self.WIDTH * self.done // self.total
        self.stream.write(f"\r[{'#' * filled}{'.' * (self.WIDTH - filled)}] {self.line()}\033[K")
        self.stream.flush()
        self._drawn = time.monotonic()

    def update(self, failed=False):
        """One more run finished (failed or not)."""
        self.done += 1
        self.failed += bool(failed)
        if self.quiet:
            return
        if self.tty:
            if self.done == self.total or time.monotonic() - self._drawn >= 0.1:
                self._draw()
            return
        tenths = 10 * self.done // self.total
        if tenths > self._tenths:
            self._tenths = tenths
            self.stream.write(f"nmdp sweep: {self.line()}\n")
            self.stream.flush()

    def finish(self):
        if self.tty:
            self._draw()
            self.stream.write("\n")
            self.stream.flush()
