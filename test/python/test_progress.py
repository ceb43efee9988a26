"""Progress lines of the long-running scripts."""
import io

from ohm_mirror_detector3d.progress import Progress


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


class Tty(io.StringIO):
    def isatty(self):
        return True


def test_a_log_gets_a_line_every_five_seconds_and_the_final_one():
    clock, log = Clock(), io.StringIO()
    progress = Progress('writer', 10, stream=log, clock=clock)
    for k in range(1, 11):
        clock.now = 2.0 * k
        progress.update(k)
    progress.finish()
    lines = log.getvalue().splitlines()
    # t = 6, 12, 18 (every 5 s or more after the previous) and the final line.
    assert lines == ['writer: 3/10 sweeps, 0.5 sweeps/s, about 14 s left',
                     'writer: 6/10 sweeps, 0.5 sweeps/s, about 8 s left',
                     'writer: 9/10 sweeps, 0.5 sweeps/s, about 2 s left',
                     'writer: 10/10 sweeps, 0.5 sweeps/s']


def test_a_quick_job_prints_only_its_summary():
    clock, log = Clock(), io.StringIO()
    progress = Progress('evaluate', 3, stream=log, clock=clock)
    for k in range(1, 4):
        clock.now = 0.1 * k
        progress.step()
    progress.finish()
    assert log.getvalue() == 'evaluate: 3/3 sweeps, 10.0 sweeps/s\n'


def test_a_terminal_line_is_rewritten_in_place():
    clock, tty = Clock(), Tty()
    progress = Progress('evaluate', 0, unit='scans', stream=tty, clock=clock)
    clock.now = 1.0
    progress.update(40)
    progress.finish()
    assert tty.getvalue() == '\revaluate: 40/? scans, 40.0 scans/s\033[K\revaluate: 40/? scans, 40.0 scans/s\033[K\n'
