"""Progress of a run in Python: a tqdm bar when tqdm imports (tqdm.auto: a widget in a
notebook, text in a terminal), else one plain line on stderr rewritten in place."""
import sys
import time


class Progress:
    def __init__(self, description):
        self._description = description
        self._bar = None
        self._shown = -1
        self._printed = False
        self._start = time.monotonic()
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return
        # delay: a run shorter than half a second shows nothing.
        self._bar = tqdm(total=100, desc=description, unit="%", delay=0.5,
                         bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")

    def __call__(self, fraction):
        percent = int(100 * fraction)
        if percent == self._shown:
            return
        if self._bar is not None:
            self._bar.update(percent - max(self._shown, 0))
        elif time.monotonic() - self._start >= 0.5:
            print(f"\r{self._description}: {percent:3d}% done", end="", file=sys.stderr,
                  flush=True)
            self._printed = True
        self._shown = percent

    def close(self):
        if self._bar is not None:
            self._bar.close()
        elif self._printed:
            print(file=sys.stderr, flush=True)
