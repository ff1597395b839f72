"""A text progress bar for long calls (progress=True of nuld.optimize and
nuld.render)."""

import sys
import time


class TextProgress:
    """Called with a long call's reports; draws
    `name [#####-----] done/total  loss L  ETA m:ss` on stderr, at most ten
    times a second. A report is the optimizer's (epoch, epochs, loss) or a
    render's (stage, done, total, status); a new stage (the sets made, then
    the tiles) starts a new line named by it."""

    def __init__(self, name, stream=None, width=24):
        self.name, self.width = name, width
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.monotonic()
        self.last = 0.0
        self.drawn = False

    def __call__(self, report):
        now = time.monotonic()
        if "epoch" in report:
            done, total = report["epoch"], report["epochs"]
            detail = "loss %.6g" % report["loss"]
        else:
            done, total, detail = report["done"], report["total"], report.get("status", "")
            stage = report.get("stage", self.name)
            if stage != self.name:  # the next stage: its own line and ETA
                self.close()
                self.name, self.start, self.last = stage, now, 0.0
        if now - self.last < 0.1 and done < total:
            return True
        self.last = now
        filled = int(self.width * done / max(total, 1))
        elapsed = now - self.start
        eta = elapsed / done * (total - done) if done else float("nan")
        eta_text = "--:--" if eta != eta else "%d:%02d" % (eta // 60, eta % 60)
        self.stream.write("\r%s [%s%s] %d/%d  %s  ETA %s" % (
            self.name, "#" * filled, "-" * (self.width - filled), done, total, detail, eta_text))
        self.stream.flush()
        self.drawn = True
        return True

    def close(self):
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False
