"""A text progress bar for long calls (nuld.optimize(progress=True))."""

import sys
import time


class TextProgress:
    """Called with the optimizer's epoch reports; draws
    `name [#####-----] epoch/epochs  loss L  ETA m:ss` on stderr, at most
    ten times a second."""

    def __init__(self, name, stream=None, width=24):
        self.name, self.width = name, width
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.monotonic()
        self.last = 0.0
        self.drawn = False

    def __call__(self, report):
        now = time.monotonic()
        done, total = report["epoch"], report["epochs"]
        if now - self.last < 0.1 and done < total:
            return True
        self.last = now
        filled = int(self.width * done / max(total, 1))
        elapsed = now - self.start
        eta = elapsed / done * (total - done) if done else float("nan")
        eta_text = "--:--" if eta != eta else "%d:%02d" % (eta // 60, eta % 60)
        self.stream.write("\r%s [%s%s] %d/%d  loss %.6g  ETA %s" % (
            self.name, "#" * filled, "-" * (self.width - filled), done, total,
            report["loss"], eta_text))
        self.stream.flush()
        self.drawn = True
        return True

    def close(self):
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False
