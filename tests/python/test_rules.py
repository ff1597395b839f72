# The CLI's rules as Python meets them (split from test_bad_inputs.py): which
# render arguments apply, progress, the set options, scipy's engine contract
# at its edges, and write_points by extension.
import subprocess

import numpy as np

import nuld
from refusals import refusal


def test_render_applies_the_clis_rules_of_what_applies():
    def render(**kw):
        return lambda: nuld.render("default", resolution=(4, 4), spp=1, **kw)
    # --max-depth under direct: one rule (RenderOverrides::checkApplicable)
    # for nuld render and nuld.render.
    for integrator in ("direct", "light", "bsdf"):
        refusal(render(integrator=integrator, max_depth=3), ValueError, "render",
                "max_depth applies to integrator path only")
    assert render(integrator="path", max_depth=3)().shape == (4, 4, 3)
    # The study's set options, for the backends that make sets only.
    for kw in (dict(opt_instances=2), dict(opt_epochs=5), dict(opt_lobe_epochs=5),
               dict(opt_nested=True), dict(opt_objective="soft"), dict(opt_union_weight=0.0)):
        refusal(render(backend="sobol", **kw), ValueError, "render", list(kw)[0],
                "applies to the study's backends that make sets")
    # The lobe options, for a backend that samples lobe tables under an
    # integrator other than light.
    for kw in (dict(lobe_mix=0.5), dict(lobe_routes="table"), dict(lobe_defensive=0.1),
               dict(lobe_bounces=1)):
        refusal(render(backend="sobol", **kw), ValueError, "render", list(kw)[0],
                "applies to a backend that samples lobe tables")
        refusal(render(backend="sobol-tabulated", integrator="light", **kw), ValueError,
                "render", list(kw)[0])
    refusal(render(assets="/tmp"), ValueError, "render", "assets applies to scene files")
    # Their values, as the CLI checks them.
    refusal(render(backend="optimized", opt_objective="l2per"), ValueError, "render",
            "opt_objective: expected 'soft' or 'l2asd'")
    refusal(render(backend="optimized", opt_union_weight=-1.0), ValueError, "render",
            "opt_union_weight: expected a weight >= 0")
    refusal(render(backend="optimized", opt_epochs=0), ValueError, "render", "opt_epochs")


def test_the_cli_refuses_max_depth_under_direct_with_the_same_rule(nuld_bin, tmp_path):
    run = subprocess.run([nuld_bin, "render", "default", "--integrator", "direct", "--max-depth",
                          "3", "--res", "4", "--spp", "1", "-q", "-o", str(tmp_path / "x.exr")],
                         capture_output=True, text=True)
    assert run.returncode == 2
    assert "--max-depth applies to --integrator path only" in run.stderr


def test_render_reports_progress_and_draws_a_bar(capfd):
    reports = []
    nuld.render("default", resolution=(40, 40), spp=1, progress=reports.append)
    assert reports and reports[-1]["stage"] == "render"
    assert reports[-1]["done"] == reports[-1]["total"] == 9  # 3 x 3 tiles of 16
    assert len(reports) <= 1001
    nuld.render("default", resolution=(8, 8), spp=1, progress=True)
    assert "render [" in capfd.readouterr().err
    nuld.render("default", resolution=(8, 8), spp=1)
    assert capfd.readouterr().err == ""  # off by default


def test_render_takes_the_clis_set_options(tmp_path, monkeypatch, nuld_bin):
    # --opt-nested, --opt-objective and --opt-union-weight as keywords: the
    # same sets (made once into the cache, then found) and the same image.
    monkeypatch.setenv("NULD_CACHE", str(tmp_path / "cache"))
    kw = dict(backend="optimized", spp=4, resolution=(8, 6), seed=3, opt_instances=2,
              opt_epochs=3, opt_objective="soft", opt_union_weight=0.5, opt_nested=True,
              stats=True)
    img, stats = nuld.render("default", **kw)
    assert stats["sets_made"] > 0
    exr = str(tmp_path / "o.exr")
    run = subprocess.run([nuld_bin, "render", "default", "--backend", "optimized", "--spp", "4",
                          "--res", "8x6", "--seed", "3", "--opt-instances", "2", "--opt-epochs",
                          "3", "--opt-objective", "soft", "--opt-union-weight", "0.5",
                          "--opt-nested", "-q", "-o", exr], capture_output=True, text=True,
                         env=dict(__import__("os").environ, NULD_CACHE=str(tmp_path / "cache")))
    assert run.returncode == 0, run.stderr
    assert "sets_made 0" in run.stdout
    assert np.array_equal(nuld.read_image(exr), img)


def test_engines_meet_scipys_contract_at_its_edges(model):
    from scipy.stats import qmc
    assert qmc.Sobol(d=2, seed=1).random(0).shape == (0, 2)
    for engine in (nuld.qmc.Sobol(d=2, seed=1), nuld.qmc.Halton(d=2, seed=1),
                   nuld.qmc.OptimizedEngine(d=2, seed=1, epochs=2),
                   nuld.qmc.PointSetEngine(nuld.sequence(4, instances=2)),
                   nuld.qmc.NeuralEngine(d=2, model=model, seed=1)):
        empty = engine.random(0)
        assert empty.shape == (0, 2) and engine.num_generated == 0
    # Every refusal names the method called, never the function underneath.
    sobol = nuld.qmc.Sobol(d=2, seed=1)
    refusal(lambda: sobol.fast_forward(3).random_base2(2), ValueError,
            "nuld.qmc.Sobol.random_base2", "m: ", "not a power of 2")
    bank = nuld.qmc.PointSetEngine(nuld.sequence(4, instances=2))
    refusal(lambda: bank.random_base2(4), ValueError, "nuld.qmc.PointSetEngine.random_base2",
            "bank holds 8")
    refusal(lambda: bank.random(9), ValueError, "nuld.qmc.PointSetEngine.random", "bank holds 8")
    refusal(lambda: bank.fast_forward(9), ValueError, "nuld.qmc.PointSetEngine.fast_forward")
    refusal(lambda: nuld.qmc.OptimizedEngine(d=2, seed=1, epochs=0).random(4), ValueError,
            "nuld.qmc.OptimizedEngine.random", "epochs")
    refusal(lambda: nuld.qmc.OptimizedEngine(n=4, seed=1, epochs=0), ValueError,
            "nuld.qmc.OptimizedEngine", "epochs")
    refusal(lambda: nuld.qmc.NeuralEngine(d=2, model=model, gamma=[0.5]), ValueError,
            "nuld.qmc.NeuralEngine", "gamma")
    refusal(lambda: nuld.qmc.PointSetEngine("no_such_file.ptsb"), RuntimeError,
            "nuld.qmc.PointSetEngine", "no_such_file.ptsb")
    # E(d=2, seed=...) for NeuralEngine, with its model as a keyword; without
    # one it has nothing to make sets with, and says so.
    neural = nuld.qmc.NeuralEngine(d=2, model=model, seed=1)
    assert neural.random(8).shape == (8, 2)
    assert np.array_equal(neural.bank, nuld.qmc.NeuralEngine(model, seed=1).bank)
    refusal(lambda: nuld.qmc.NeuralEngine(d=2, seed=1), TypeError, "nuld.qmc.NeuralEngine",
            "model: expected the path of a model")
    refusal(lambda: nuld.qmc.NeuralEngine(d=3, model=model), ValueError,
            "nuld.qmc.NeuralEngine", "2-dimensional")


def test_write_points_writes_by_extension(tmp_path, nuld_bin):
    bank = nuld.sequence(5, instances=3, seed=1)
    one = nuld.sequence(7, seed=2)
    # .npy: numpy.load gives the shape nuld export writes, (K, N, 2).
    nuld.write_points(str(tmp_path / "b.npy"), bank)
    nuld.write_points(str(tmp_path / "one.npy"), one)
    assert np.array_equal(np.load(str(tmp_path / "b.npy")), bank)
    assert np.array_equal(np.load(str(tmp_path / "one.npy")), one[None])
    nuld.write_points(str(tmp_path / "b.txt"), bank, {"comment": "c"})
    subprocess.run([nuld_bin, "export", str(tmp_path / "b.txt"), "-o", str(tmp_path / "e.npy")],
                   check=True, capture_output=True)
    assert (tmp_path / "e.npy").read_bytes() == (tmp_path / "b.npy").read_bytes()
    for ext in (".csv", ".dat"):
        nuld.write_points(str(tmp_path / ("b" + ext)), bank)
        subprocess.run([nuld_bin, "export", str(tmp_path / "b.txt"), "-o",
                        str(tmp_path / ("e" + ext))], check=True, capture_output=True)
        assert (tmp_path / ("e" + ext)).read_bytes() == (tmp_path / ("b" + ext)).read_bytes()
    assert np.array_equal(nuld.read_points(str(tmp_path / "b.dat"))[0], bank)
    # .txt and .ptsb keep the metadata; the points-only formats refuse it.
    refusal(lambda: nuld.write_points(str(tmp_path / "m.npy"), bank, {"comment": "c"}),
            ValueError, "write_points", "metadata", ".npy")
    for name in ("o.xyz", "o", "o.NPY", "o.pts"):
        refusal(lambda: nuld.write_points(str(tmp_path / name), bank), ValueError,
                "write_points", "path", "expected a name ending in .txt")
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "b.csv", "b.dat", "b.npy", "b.txt", "e.csv", "e.dat", "e.npy", "one.npy"]
