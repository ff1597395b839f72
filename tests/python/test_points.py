# Targets, sequences, discrepancies, the optimizer and point-set files from
# Python, checked against the CLI's values and against scipy.
import numpy as np
import pytest
from scipy.stats import qmc

import nuld


def test_targets_from_specs():
    u = nuld.Target("uniform")
    assert u.is_uniform and u.spec == "uniform" and u.domain == "square"
    assert np.all(u.pdf(np.full((5, 2), 0.3)) == 1)
    g = nuld.Target("gaussian:0.3,0.6,0.1")
    assert repr(g).startswith("nuld.Target('gaussian")
    assert g.mass((0, 0), (1, 1)) == pytest.approx(1, abs=1e-9)
    assert g.pdf(np.array([[0.3, 0.6]]))[0] > g.pdf(np.array([[0.9, 0.1]]))[0]
    # pdf keeps the instances' axis
    assert g.pdf(np.zeros((3, 4, 2))).shape == (3, 4)


def test_bad_input_raises_with_the_clis_message():
    with pytest.raises(ValueError, match="gaussian"):
        nuld.Target("gaussian:banana")
    with pytest.raises(ValueError, match=r"shape \(N, 2\) or \(K, N, 2\)"):
        nuld.Target("uniform").pdf(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="unknown metric 'l3'"):
        nuld.discrepancy(np.zeros((4, 2)), "l3")
    # An unknown setting is an unknown keyword, as Python has it: a TypeError.
    with pytest.raises(TypeError, match="optimize: unknown keyword 'epoch'; did you mean 'epochs'"):
        nuld.optimize("uniform", 4, epoch=3)
    with pytest.raises(RuntimeError, match="no_such_file.ptsb"):
        nuld.read_points("no_such_file.ptsb")


def test_sequences_are_deterministic_and_map_through_targets():
    a = nuld.sequence(16, "sobol", "owen", seed=3)
    assert a.shape == (16, 2) and a.dtype == np.float64
    assert np.array_equal(a, nuld.sequence(16, seed=3, kind="sobol"))
    assert not np.array_equal(a, nuld.sequence(16, seed=4))
    bank = nuld.sequence(8, instances=3, seed=3)
    assert bank.shape == (3, 8, 2)
    # N = 1 and N not a power of two
    assert nuld.sequence(1).shape == (1, 2)
    assert nuld.sequence(7, "halton").shape == (7, 2)
    target = nuld.Target("gaussian:0.3,0.6,0.1")
    mapped = nuld.sequence(16, seed=3, target="gaussian:0.3,0.6,0.1")
    assert np.array_equal(mapped, target.invert(a))
    assert np.all(target.pdf(mapped) > 0)


@pytest.mark.parametrize("n", [1, 7, 16, 100])
def test_l2star_agrees_with_scipy(n):
    # scipy's L2-star discrepancy is the plain (not squared) value nuld
    # prints (nuld eval, nuld.discrepancy): two implementations, one number.
    for points in (nuld.sequence(n, seed=5), np.random.default_rng(n).random((n, 2))):
        ours = nuld.discrepancy(points, "l2star")
        assert isinstance(ours, float)
        theirs = qmc.discrepancy(points, method="L2-star")
        assert ours == pytest.approx(theirs, rel=1e-10)


def test_discrepancy_matches_the_cli(tmp_path, nuld_bin):
    import subprocess
    bank = nuld.sequence(32, instances=2, seed=9)
    path = str(tmp_path / "s.txt")
    nuld.write_points(path, bank, {"comment": "from python"})
    out = subprocess.run([nuld_bin, "eval", path, "--metric", "all"], check=True,
                         capture_output=True, text=True).stdout
    cli = dict((k, float(v)) for k, v in (line.split() for line in out.splitlines()))
    for metric in ("l2star", "l2asd", "dstar", "l2per"):
        assert nuld.discrepancy(bank, metric).mean() == pytest.approx(cli[metric], rel=1e-8)


def test_point_files_round_trip(tmp_path):
    bank = nuld.sequence(5, instances=3, seed=1)
    for name in ("a.txt", "a.ptsb"):
        path = str(tmp_path / name)
        nuld.write_points(path, bank, {"comment": "x y"})
        back, meta = nuld.read_points(path)
        assert back.shape == (3, 5, 2)
        assert np.array_equal(back, bank)
        assert meta["comment"] == "x y"


def test_optimize_lowers_the_loss_and_reports_progress():
    reports = []
    start = nuld.optimize("uniform", 16, instances=2, objective="l2asd", epochs=1, seed=2)
    done = nuld.optimize("uniform", 16, instances=2, objective="l2asd", epochs=200, seed=2,
                         lr=(1e-2, 1e-4), progress=lambda r: reports.append(r) or True)
    assert done.shape == (2, 16, 2)
    assert len(reports) == 200 and reports[-1]["epoch"] == 200
    assert np.all(nuld.discrepancy(done, "l2asd") < nuld.discrepancy(start, "l2asd"))
    # a False answer stops the run there
    calls = []
    nuld.optimize("uniform", 8, objective="l2asd", epochs=50,
                  progress=lambda r: calls.append(r) or len(calls) < 5)
    assert len(calls) == 5


def test_long_work_releases_the_gil():
    import threading
    import time
    ticks = []
    done = threading.Event()

    def work():
        nuld.optimize("uniform", 256, instances=2, objective="l2asd", epochs=300)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks.append(time.monotonic())
        time.sleep(0.001)
    t.join()
    assert len(ticks) > 20  # the main thread ran while the optimizer did


def test_nested_prefixes_against_scipys_l2_star(tmp_path, nuld_bin):
    # Every prefix of a nested bank, as nuld eval prints it (METRIC@M),
    # against scipy's independent L2-star of the same first M points.
    import subprocess
    from scipy.stats import qmc
    bank = nuld.optimize("uniform", 32, 3, epochs=150, nested=4, nested_power=2, seed=2)
    path = str(tmp_path / "nested.ptsb")
    nuld.write_points(path, bank, {"prefixes": "4,8,16,32"})
    out = subprocess.run([nuld_bin, "eval", path, "--metric", "l2star"], check=True,
                         capture_output=True, text=True).stdout
    values = dict(line.split() for line in out.splitlines())
    for m in (4, 8, 16):
        ours = float(values["l2star@%d" % m])
        theirs = np.mean([qmc.discrepancy(s[:m], method="L2-star") for s in bank])
        assert ours == pytest.approx(theirs, rel=1e-6), m
