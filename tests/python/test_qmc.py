# The scipy.stats.qmc engines over nuld's banks: the QMCEngine contract
# (random, reset, fast_forward, num_generated) and scipy's own functions
# working on them unchanged.
import numpy as np
import pytest
from scipy.stats import qmc

import nuld
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
