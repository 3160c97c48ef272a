"""Progress of long calls: a bar only where someone watches, milestones in the log always, and the
same results with or without the bar."""

import logging
import math
import sys

import numpy as np
import xarray as xr

from vibroimpact import _progress
from vibroimpact._progress import Progress


def test_the_bar_shows_when_asked_and_the_log_gets_every_tenth(capsys, caplog):
    with caplog.at_level(logging.INFO, logger="vibroimpact"):
        with Progress(20, "demo work", True, unit="item") as bar:
            for _ in range(20):
                bar.update()
    err = capsys.readouterr().err
    assert "demo work" in err and "/20" in err  # tqdm redraws at most every 0.1 s: the count it shows varies
    msgs = [r.getMessage() for r in caplog.records]
    assert msgs[0] == "demo work: started (20 item)" and msgs[-1].startswith("demo work: done, 20 in")
    assert [m.split()[2] for m in msgs[1:-1]] == [f"{k}/20" for k in range(2, 21, 2)]


def test_no_bar_where_nobody_watches(capsys, monkeypatch):
    """Default: no bar when standard error is not a terminal, nor inside a Snakemake job even on one."""
    with Progress(5, "quiet", None) as bar:
        bar.update(5)
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    monkeypatch.setitem(sys.modules, "snakemake", object())
    assert not _progress.interactive()
    monkeypatch.delitem(sys.modules, "snakemake")
    assert _progress.interactive()


def test_a_sweep_and_a_batch_give_the_same_results_with_the_bar(capsys):
    """The bar runs a batch in tenths instead of one parallel call: every run is the same."""
    from vibroimpact.analysis.sweeps import sweep
    from vibroimpact.analysis.windows import attractor_batch

    g = 0.1245 * 9.8 * math.sin(math.pi / 6) / 5.0
    d = np.linspace(0.13, 0.3, 40)
    quiet = attractor_batch(d, g, 0.5, 1.0, 0.3, max_periods=50, progress=False)
    shown = attractor_batch(d, g, 0.5, 1.0, 0.3, max_periods=50, progress=True, desc="test batch")
    xr.testing.assert_identical(quiet, shown)
    assert "test batch" in capsys.readouterr().err
    a = sweep("s", np.linspace(0.25, 0.3, 6), beta=math.pi / 6, max_periods=50, progress=False)
    b = sweep("s", np.linspace(0.25, 0.3, 6), beta=math.pi / 6, max_periods=50, progress=True)
    xr.testing.assert_identical(a, b)
    assert "sweep of s" in capsys.readouterr().err
