"""Progress of the long-running scripts (simulated bags, evaluation) on stderr.

"synthesize_sweep: 3/10 sweeps, 1.4 sweeps/s, about 5 s left": rewritten in place on a terminal,
a line every few seconds otherwise (a log file, roslaunch's output), like prefilter_bag's.
"""
import sys
import time


class Progress:
    def __init__(self, what, total, unit='sweeps', stream=None, clock=time.monotonic):
        self.what, self.total, self.unit = what, total, unit
        self.stream = sys.stderr if stream is None else stream
        self.clock = clock
        self.tty = bool(getattr(self.stream, 'isatty', lambda: False)())
        self.interval = 0.5 if self.tty else 5.0
        self.start = clock()
        self.printed_at = None
        self.done = 0

    def line(self):
        elapsed = self.clock() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        text = '%s: %d/%s %s, %.1f %s/s' % (self.what, self.done, self.total if self.total else '?', self.unit,
                                             rate, self.unit)
        if self.total and 0 < self.done < self.total and rate > 0:
            text += ', about %.0f s left' % ((self.total - self.done) / rate)
        return text

    def update(self, done, last=False):
        """`done` items finished; prints when the last print is old enough (always when `last`)."""
        self.done = done
        now = self.clock()
        if not last and self.printed_at is not None and now - self.printed_at < self.interval:
            return
        if not last and self.printed_at is None and now - self.start < self.interval:
            return  # quick jobs print only their final line
        self.printed_at = now
        if self.tty:
            self.stream.write('\r' + self.line() + '\033[K' + ('\n' if last else ''))
        else:
            self.stream.write(self.line() + '\n')
        self.stream.flush()

    def finish(self):
        self.update(self.done, last=True)

    def step(self):
        self.update(self.done + 1)
