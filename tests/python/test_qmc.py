# The scipy.stats.qmc engines over nuld's banks: the QMCEngine contract
# (random, reset, fast_forward, num_generated) and scipy's own functions
# working on them unchanged.
import warnings

import numpy as np
import pytest
from scipy.stats import qmc

import nuld
import nuld.qmc
from nuld.qmc import OptimizedEngine, PointSetEngine


def test_point_set_engine_serves_the_bank_in_order():
    bank = nuld.sequence(8, instances=3, seed=1)
    e = PointSetEngine(bank)
    assert isinstance(e, qmc.QMCEngine) and e.d == 2 and e.n == 8
    assert np.array_equal(e.random(8), bank[0])
    assert np.array_equal(e.random(8), bank[1])
    assert e.num_generated == 16
    e.reset()
    assert e.num_generated == 0 and np.array_equal(e.random(8), bank[0])
    e.reset().fast_forward(16)
    assert np.array_equal(e.random(3), bank[2][:3])
    with pytest.raises(ValueError, match="bank holds 24"):
        e.random(8)
    with pytest.raises(ValueError, match="cannot skip"):
        e.fast_forward(100)
    with pytest.raises(ValueError, match="shape"):
        PointSetEngine(np.zeros((4, 3)))


def test_scipy_functions_work_on_the_engines_points():
    e = OptimizedEngine("uniform", n=16, instances=2, objective="l2asd", epochs=100, seed=4)
    sets = [e.random(16) for _ in range(2)]
    for s, ours in zip(sets, nuld.discrepancy(e.bank, "l2star")):
        assert qmc.discrepancy(s, method="L2-star") == pytest.approx(ours, rel=1e-10)
    # scipy's scaling of [0, 1)^2 points to bounds
    scaled = qmc.scale(sets[0], [0, 10], [1, 20])
    assert scaled.shape == (16, 2) and scaled[:, 1].min() >= 10


def test_engine_from_a_point_file(tmp_path):
    bank = nuld.sequence(4, instances=2, seed=2)
    path = str(tmp_path / "b.ptsb")
    nuld.write_points(path, bank, {"comment": "c"})
    e = PointSetEngine(path)
    assert e.metadata["comment"] == "c"
    assert np.array_equal(e.random(8), bank.reshape(-1, 2))


def test_neural_engine_serves_a_models_sets(tmp_path, nuld_bin):
    import subprocess
    model = str(tmp_path / "tiny.nuldnet")
    subprocess.run([nuld_bin, "train", "--target", "uniform", "--n", "16", "--hidden", "64",
                    "--steps", "3", "-q", "-o", model], check=True, capture_output=True)
    points, spec = nuld.generate_neural(model, instances=3, seed=5)
    assert points.shape == (3, 16, 2) and spec == "uniform"
    assert np.all((points >= 0) & (points < 1))
    again, _ = nuld.generate_neural(model, instances=3, seed=5)
    assert np.array_equal(points, again)  # a pure function of (model, seed)
    from nuld.qmc import NeuralEngine
    e = NeuralEngine(model, instances=3, seed=5)
    assert e.target_spec == "uniform" and np.array_equal(e.random(16), points[0])
    with pytest.raises(ValueError, match="gamma"):
        nuld.generate_neural(model, gamma=[0.5])


# As scipy tests its own engines (scipy/stats/tests/test_qmc.py): every
# engine built as E(d=2, seed=...), reset and fast_forward reproduce the
# stream, random_base2, a bad d or seed refused, a partial set warned about.
ENGINES = [
    ("sobol", lambda **kw: nuld.qmc.Sobol(**kw)),
    ("halton", lambda **kw: nuld.qmc.Halton(**kw)),
    ("optimized", lambda **kw: OptimizedEngine(epochs=40, **kw)),
]


@pytest.mark.parametrize("name,make", ENGINES)
@pytest.mark.parametrize("seed", [None, 7, "generator"])
def test_engines_are_built_and_replayed_as_scipys(name, make, seed):
    if seed == "generator":
        seed = np.random.default_rng(3)
    engine = make(d=2, seed=seed)
    assert isinstance(engine, qmc.QMCEngine) and engine.d == 2
    ref = engine.random(n=8)
    assert ref.shape == (8, 2) and np.all((ref >= 0) & (ref < 1))
    engine.reset()
    assert np.array_equal(engine.random(n=8), ref)
    engine.reset()
    engine.fast_forward(4)
    # A partial set of an optimized engine warns; the points are the same.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert np.array_equal(engine.random(n=4), ref[4:8])
    assert engine.num_generated == 8
    engine.reset()
    assert engine.random_base2(3).shape == (8, 2)


def test_scipy_snippet_runs_unchanged_over_nulds_engines():
    rows = []
    for E in [qmc.Sobol, qmc.Halton, nuld.qmc.Sobol, nuld.qmc.Halton, nuld.qmc.OptimizedEngine]:
        for s in range(2):
            rows.append((E.__name__, qmc.discrepancy(E(d=2, seed=s).random(16))))
    assert len(rows) == 10 and all(np.isfinite(d) and d > 0 for _, d in rows)


def test_nulds_sequences_continue_and_match_the_renderers():
    e = nuld.qmc.Sobol(d=2, seed=5)
    assert np.array_equal(np.concatenate([e.random(16), e.random(16)]),
                          nuld.sequence(32, kind="sobol", seed=5))
    h = nuld.qmc.Halton(d=2, seed=5)
    assert np.array_equal(np.concatenate([h.random(3), h.random(9)]),
                          nuld.sequence(12, kind="halton", seed=5))


@pytest.mark.parametrize("make", [nuld.qmc.Sobol, nuld.qmc.Halton, OptimizedEngine])
def test_other_dimensions_and_bad_seeds_are_refused(make):
    for d in (1, 3, 2.0, True):
        with pytest.raises(ValueError, match="2-dimensional"):
            make(d=d)
    for seed, error in ((-1, ValueError), (2**64, ValueError), (1.5, TypeError),
                        ("s", TypeError)):
        with pytest.raises(error, match="seed: expected None, a whole number from 0 to "
                                        r"2\^64 - 1 or a numpy.random.Generator"):
            make(d=2, seed=seed)


def test_partial_sets_warn_as_scipys_sobol_does():
    with pytest.warns(UserWarning, match="power of 2"):
        qmc.Sobol(d=2, seed=1).random(6)
    with pytest.warns(UserWarning, match="power of 2"):
        nuld.qmc.Sobol(d=2, seed=1).random(6)
    e = OptimizedEngine(d=2, seed=1, epochs=40)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        e.random(8)  # whole sets: silent
        e.random(8)  # the next set, optimized on demand
    assert e.bank.shape == (2, 8, 2)
    with pytest.warns(UserWarning, match="partial set"):
        e.random(3)
    with pytest.raises(ValueError, match="not a power of 2"):
        nuld.qmc.Sobol(d=2, seed=1).fast_forward(3).random_base2(2)


def test_the_module_has_a_version_as_the_cli():
    import re
    assert re.fullmatch(r"\d+\.\d+\.\d+", nuld.__version__)


def test_the_classic_sets_and_pmj02_engine():
    # Every elementary interval of area 1/16 holds one of 16 pmj02 points
    # (each of the five shapes); stratified 16 fills the 4 x 4 grid; the
    # lattice's 16 points differ pairwise by multiples of one vector mod 1.
    def one_per_interval(p, m):
        for a in range(m + 1):
            cells = (np.floor(p[:, 0] * 2**a) * 2**(m - a) + np.floor(p[:, 1] * 2**(m - a)))
            if len(np.unique(cells)) != len(p):
                return False
        return True

    pmj = nuld.qmc.PMJ02(d=2, seed=3).random(16)
    assert pmj.shape == (16, 2) and one_per_interval(pmj, 4)
    grid = nuld.sequence(16, kind="stratified", seed=3)
    assert len(np.unique(np.floor(grid * 4) @ [4, 1])) == 16
    lattice = nuld.sequence(16, kind="lattice", scramble="none")
    assert np.allclose(np.sort(lattice[:, 0]), np.arange(16) / 16)
    # Projection-regular: y takes all 16 values too (a generator sharing a
    # factor with 16 would give fewer).
    assert np.allclose(np.sort(lattice[:, 1]), np.arange(16) / 16)
    with pytest.raises(ValueError, match="stratified"):
        nuld.sequence(16, kind="stratified", scramble="owen")
    # baker: the cp set of the same seed, each coordinate folded.
    shifted = nuld.sequence(64, kind="lattice", scramble="cp", seed=9)
    folded = nuld.sequence(64, kind="lattice", scramble="baker", seed=9)
    assert np.array_equal(folded, 1 - np.abs(2 * shifted - 1))
    with pytest.raises(ValueError, match="baker.*expected lattice"):
        nuld.sequence(16, kind="sobol", scramble="baker")


def test_every_power_of_two_prefix_of_generated_pmj02_sets_is_a_02_net(tmp_path, nuld_bin):
    # nuld generate --sequence pmj02, read back: for every instance and
    # every prefix of 2^m points, one point in each elementary interval of
    # every shape 2^-a x 2^-(m-a).
    import subprocess
    out = tmp_path / "pmj.txt"
    subprocess.run([nuld_bin, "generate", "--sequence", "pmj02", "--n", "256", "--instances", "3",
                    "--seed", "5", "-o", str(out)], check=True, capture_output=True)
    sets = nuld.read_points(str(out))[0]  # (points, metadata)
    assert sets.shape == (3, 256, 2)
    for points in sets:
        for m in range(9):
            prefix = points[:2**m]
            for a in range(m + 1):
                cells = np.floor(prefix[:, 0] * 2**a) * 2**(m - a) + np.floor(
                    prefix[:, 1] * 2**(m - a))
                assert len(np.unique(cells)) == 2**m, (m, a)
