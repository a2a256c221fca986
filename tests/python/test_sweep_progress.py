"""The sweep's progress on stderr (nmdp.sweep.progress): a bar redrawn in place on a terminal, one
line per tenth of the runs to a file, nothing when quiet."""
import io

from nmdp.sweep.progress import Progress


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_to_a_file_one_line_per_tenth_of_the_runs_with_failures_and_an_estimate():
    out = io.StringIO()
    p = Progress(40, stream=out)
    for i in range(40):
        p.update(failed=i in (5, 6))
    p.finish()
    lines = out.getvalue().splitlines()
    assert len(lines) == 10
    assert lines[0].startswith("nmdp sweep: 4/40 runs, 0:00 elapsed, ETA ")
    assert lines[1].startswith("nmdp sweep: 8/40 runs, 2 failed, 0:00 elapsed, ETA ")
    assert lines[-1] == "nmdp sweep: 40/40 runs, 2 failed, 0:00 elapsed"


def test_fewer_runs_than_ten_give_a_line_each():
    out = io.StringIO()
    p = Progress(3, stream=out)
    for _ in range(3):
        p.update()
    assert [ln.split(",")[0] for ln in out.getvalue().splitlines()] == [f"nmdp sweep: {i}/3 runs" for i in (1, 2, 3)]


def test_on_a_terminal_a_bar_redrawn_in_place_ending_with_a_newline():
    out = Terminal()
    p = Progress(4, stream=out)
    for _ in range(4):
        p.update()
    p.finish()
    text = out.getvalue()
    assert text.startswith("\r[" + "." * Progress.WIDTH + "] 0/4 runs")
    assert "\r[" + "#" * Progress.WIDTH + "] 4/4 runs, 0:00 elapsed\033[K" in text
    assert text.endswith("\n") and text.count("\n") == 1


def test_quiet_writes_nothing_even_on_a_terminal():
    out = Terminal()
    p = Progress(4, stream=out, quiet=True)
    for _ in range(4):
        p.update(failed=True)
    p.finish()
    assert out.getvalue() == "" and p.failed == 4
