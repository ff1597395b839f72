# Your own sampler as a row (tools/python/README.md, "Your own sampler"):
# a scipy.stats.qmc engine or a callable through render(sampler=...), a C
# plugin through backend='plugin:PATH', and nuld.study over both, with the
# studies' statistics.
import math
import os

import numpy as np
import pytest
from scipy.stats import qmc

import nuld

SMALL = dict(resolution=(24, 16), spp=4)


@pytest.fixture(scope="module")
def example_plugin():
    path = os.environ.get("NULD_EXAMPLE_PLUGIN")
    if not path:
        pytest.skip("the example plugin is not known (set NULD_EXAMPLE_PLUGIN)")
    return path


def test_an_engine_renders_the_same_image_for_any_thread_count():
    one = nuld.render("default", sampler=qmc.Sobol(d=2, seed=5), threads=1, **SMALL)
    every = nuld.render("default", sampler=qmc.Sobol(d=2, seed=5), **SMALL)
    assert np.array_equal(one, every)
    # The engine advances: the same engine again draws other points.
    engine = qmc.Sobol(d=2, seed=5)
    first = nuld.render("default", sampler=engine, **SMALL)
    assert np.array_equal(first, one)
    assert not np.array_equal(nuld.render("default", sampler=engine, **SMALL), first)


def test_an_engine_and_a_callable_tie_the_words_they_resemble():
    # Twelve seeds under direct (paths' fireflies make single renders
    # useless): a scipy Sobol engine against per-pixel sobol, numpy's random
    # numbers against independent. A dealing that matched pairs by index
    # would be biased and off by far more.
    small = dict(resolution=(24, 16), spp=4, integrator="direct")
    ref = nuld.render("default", backend="halton", spp=1024, seed=999, **{
        k: v for k, v in small.items() if k != "spp"})

    def mse(render):
        return np.mean([nuld.compare(render(s), ref)["mse"] for s in range(1, 13)])

    def numpy_sampler(seed):
        rng = np.random.default_rng(seed)
        return lambda n: rng.random((n, 2))
    sobol = mse(lambda s: nuld.render("default", backend="sobol", seed=s, **small))
    engine = mse(lambda s: nuld.render("default", sampler=qmc.Sobol(d=2, seed=s), **small))
    independent = mse(lambda s: nuld.render("default", backend="independent", seed=s, **small))
    draws = mse(lambda s: nuld.render("default", sampler=numpy_sampler(s), **small))
    assert 0.5 < engine / sobol < 2, (engine, sobol)
    assert 0.5 < draws / independent < 2, (draws, independent)


def test_sampler_domains_leave_the_rest_to_sobol():
    _, stats = nuld.render("default", sampler=qmc.Halton(d=2, seed=1), sampler_domains=1,
                           stats=True, **SMALL)
    assert stats["backend"] == "sampler:Halton"
    assert "the sampler serves 1 of the" in stats["note"]


def test_a_sampler_that_takes_a_domain_is_told_its_role():
    seen = []

    def latin(n, domain):
        seen.append((domain["role"], domain["bounce"], domain["dimensions"], domain["integrator"]))
        rng = np.random.default_rng(len(seen))
        k = domain["dimensions"]
        # n rooks: each column a permutation of n strata, jittered.
        return (np.stack([rng.permutation(n) for _ in range(k)], axis=1)
                + rng.random((n, k))) / n

    image = nuld.render("cornell", sampler=latin, integrator="path", max_depth=2, **SMALL)
    assert np.isfinite(image).all() and image.mean() > 0
    roles = {r for r, _, _, _ in seen}
    assert roles == {"camera", "light-choice", "light", "lobe-choice", "bsdf", "roulette"}, roles
    assert all(d == (2 if r in ("camera", "light", "bsdf") else 1) for r, _, d, _ in seen)
    assert {b for _, b, _, _ in seen} == {0, 1}
    assert {i for _, _, _, i in seen} == {"path"}


def refusal(call, kind, *words):
    with pytest.raises(kind) as e:
        call()
    text = str(e.value)
    for w in words:
        assert w in text, text
    return text


def test_bad_samplers_are_refused_in_words():
    def render(**kw):
        return lambda: nuld.render("default", **SMALL, **kw)
    refusal(render(sampler=qmc.Sobol(d=3)), ValueError, "render: sampler:", "d = 3")
    refusal(render(sampler=5), TypeError, "render: sampler:", "(got int)")
    refusal(render(sampler=lambda n: np.zeros((n, 3))), ValueError, "returned shape", ", 3)")
    refusal(render(sampler=lambda n: "points"), ValueError, "returned str")
    refusal(render(sampler=lambda n: None), TypeError, "returned NoneType")
    refusal(render(sampler=lambda n: np.full((n, 2), 1.0)), ValueError, "gave (1, 1)",
            "expected numbers in [0, 1)")
    refusal(render(sampler=lambda n: np.full((n, 2), np.nan)), ValueError, "gave (nan")
    refusal(render(sampler=lambda n, domain: np.zeros((n, 2))), ValueError, "domain={'index': 1",
            "returned shape", "expected (")
    refusal(render(sampler=qmc.Sobol(d=2), backend="sobol"), ValueError, "backend: not with sampler")
    refusal(render(sampler_domains=1), ValueError, "sampler_domains applies to a sampler only")
    refusal(render(sampler=qmc.Sobol(d=2), sampler_domains=0), ValueError, "sampler_domains")

    def broken(n):
        raise ZeroDivisionError("the user's own error")
    refusal(render(sampler=broken), ZeroDivisionError, "the user's own error")


def test_the_study_helper_is_the_loop_it_summarizes(example_plugin):
    rows = {"sobol": "sobol", "plugin": "plugin:" + example_plugin,
            "scipy": lambda s: qmc.Sobol(d=2, seed=s)}
    reference = nuld.render("default", backend="halton", spp=64, resolution=(24, 16), seed=99)
    table = nuld.study("default", rows=rows, spp=(2, 4), repeats=3, seed=11, reference=reference,
                       resolution=(24, 16))
    assert [(r["row"], r["spp"]) for r in table] == [
        (label, n) for label in rows for n in (2, 4)]
    # The plugin's cell at 4 spp, by hand: the mean and error of its repeats'
    # MSE, and the ratio to sobol's with the studies' verdict.
    def mses(backend):
        return [nuld.compare(nuld.render("default", backend=backend, spp=4, seed=11 + r,
                                         resolution=(24, 16)), reference)["mse"]
                for r in range(3)]
    mine, sobol = nuld.mean_and_error(mses("plugin:" + example_plugin)), \
        nuld.mean_and_error(mses("sobol"))
    row = next(r for r in table if r["row"] == "plugin" and r["spp"] == 4)
    assert row["mse"] == pytest.approx(mine["mean"], rel=1e-12)
    assert row["mse_stderr"] == pytest.approx(mine["stderr"], rel=1e-12)
    q = nuld.ratio_of_means(mine["mean"], mine["stderr"], sobol["mean"], sobol["stderr"])
    assert row["mse_ratio"] == pytest.approx(q["ratio"]) and row["verdict"] == q["verdict"]
    assert row["verdict"] in ("better", "tie", "worse")
    base = next(r for r in table if r["row"] == "sobol")
    assert base["verdict"] == "-" and math.isnan(base["mse_ratio"])
    assert "mse/sobol" in str(table)


def test_the_study_helper_writes_csv_and_refuses_bad_rows(tmp_path):
    table = nuld.study("default", rows=["sobol", "halton"], spp=2, repeats=2,
                       reference_spp=16, resolution=(12, 8))
    assert table.reference_variance > 0
    path = tmp_path / "study.csv"
    table.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0].startswith("row,spp,repeats,mse") and len(lines) == 3
    refusal(lambda: nuld.study("default", rows={"x": 3}, resolution=(4, 4)), TypeError,
            "study: row 'x': expected a backend word")
    refusal(lambda: nuld.study("default", rows=["sobol"], baseline="halton", resolution=(4, 4)),
            ValueError, "study: baseline")
    refusal(lambda: nuld.study("default", repeats=0, resolution=(4, 4)), ValueError,
            "study: repeats")


def test_a_plain_callable_and_a_long_label_are_rows(example_plugin):
    # A sampler n -> (n, 2) is a row as it stands (no factory around it),
    # labels are printed whole, and a row's failure names the study and the row.
    rng = np.random.default_rng(5)
    label = "my-own-plugin-with-a-label-longer-than-the-column"
    rows = {"sobol": "sobol", "plain": lambda n: rng.random((n, 2)),
            label: "plugin:" + example_plugin}
    table = nuld.study("default", rows=rows, spp=2, repeats=2, reference_spp=16,
                       resolution=(12, 8))
    assert [r["row"] for r in table] == list(rows)
    assert all(math.isfinite(r["mse"]) for r in table)
    assert label in str(table)
    refusal(lambda: nuld.study("default", rows={"bad": lambda n: np.zeros((n, 3))}, spp=2,
                               repeats=1, reference_spp=16, resolution=(4, 4)),
            ValueError, "study: row 'bad': ")


def test_the_study_helpers_reference_spp_is_the_clis(nuld_bin):
    # One default for both front ends: the CLI's help states its own.
    import inspect
    import re
    import subprocess
    help_text = subprocess.run([nuld_bin, "study", "render", "--help"], check=True,
                               capture_output=True, text=True).stdout
    cli = re.search(r"--reference-spp[^\n]*\n[^(]*\(default (\d+)", help_text)
    assert cli, "the CLI's help names no --reference-spp default"
    assert inspect.signature(nuld.study).parameters["reference_spp"].default == int(cli.group(1))


def test_stats_and_statistics_functions():
    assert nuld.mean_and_error([2.0])["stderr"] == 0
    e = nuld.mean_and_error([1.0, 2.0, 3.0])
    assert e["mean"] == 2 and e["std"] == 1 and e["stderr"] == pytest.approx(1 / math.sqrt(3))
    assert nuld.ratio_of_means(1, 0.01, 2, 0.02)["verdict"] == "better"
    assert nuld.ratio_of_means(1, 0.3, 1.1, 0.3)["verdict"] == "tie"
    assert nuld.ratio_of_means(1, 0, 1, 0)["verdict"] == "n/a"
    img = nuld.render("default", **SMALL)
    assert nuld.compare(img, img)["screen"] == 0


def test_a_point_file_without_a_target_serves_with_a_note(tmp_path):
    # Points written without metadata may already be mapped to a target:
    # they serve as uniform primary samples only with a note saying so.
    path = str(tmp_path / "plain.txt")
    nuld.write_points(path, nuld.sequence(4, instances=2))
    _, stats = nuld.render("default", backend="optimized:" + path, stats=True, **SMALL)
    assert "plain.txt: names no target" in stats["note"], stats
    assert "uniform primary samples" in stats["note"], stats
