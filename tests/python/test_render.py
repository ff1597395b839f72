# Rendering from Python: the image the CLI writes, bit for bit; images
# compared; bad input refused with the CLI's message.
import os
import re
import subprocess

import numpy as np
import pytest

import nuld


def test_every_backend_word_renders(tmp_path, nuld_bin):
    # The words `nuld help backends` prints (the registry's), aliases included.
    text = subprocess.run([nuld_bin, "help", "backends"], check=True, capture_output=True,
                          text=True).stdout.split("Renders only")[0]
    words = [line.split()[0] for line in text.splitlines() if line.startswith("  ")
             and line[2].isalpha()]
    flat = " ".join(text.split())
    words += [w.rstrip(")") for part in flat.split("(also: ")[1:] for w in [part.split(")")[0]]]
    sets = str(tmp_path / "u4.txt")
    subprocess.run([nuld_bin, "generate", "--sequence", "sobol", "--n", "4", "-o", sets],
                   check=True, capture_output=True)
    model = str(tmp_path / "u4.nuldnet")
    subprocess.run([nuld_bin, "train", "--target", "uniform", "--n", "4", "--hidden", "8",
                    "--steps", "2", "--batch", "2", "--boxes", "64", "-q", "-o", model],
                   check=True, capture_output=True)
    assert len(words) >= 9, words
    # An optional argument: the word alone (neural: the shipped model) and with it.
    words = [w for word in words for w in ([word.split("[")[0], word.replace("[", "").replace(
        "]", "")] if "[" in word else [word])]
    for word in words:
        # plugin:PATH[:ARGS]: the example plugin, which takes no ARGS.
        backend = word.replace("PATHS", sets).replace("MODEL", model).replace(
            "PATH", os.environ["NULD_EXAMPLE_PLUGIN"]).replace("ARGS", "")
        img = nuld.render("default", backend=backend, spp=4, resolution=(8, 6))
        assert np.all(np.isfinite(img)), word


def test_render_is_the_clis_image(tmp_path, nuld_bin):
    img, stats = nuld.render("default", backend="sobol", spp=2, resolution=(24, 16), seed=3,
                             integrator="direct", stats=True)
    assert img.shape == (16, 24, 3) and img.dtype == np.float32
    assert np.all(np.isfinite(img)) and img.mean() > 0
    assert stats["spp"] == 2 and stats["rejected_samples"] == 0
    exr = str(tmp_path / "r.exr")
    subprocess.run([nuld_bin, "render", "default", "--backend", "sobol", "--spp", "2", "--res",
                    "24x16", "--seed", "3", "--integrator", "direct", "-q", "-o", exr],
                   check=True, capture_output=True)
    assert np.array_equal(nuld.read_image(exr), img)
    attributes = nuld.read_image_attributes(exr)
    assert attributes["nuld:backend"] == "sobol" and attributes["nuld:spp"] == "2"
    assert attributes["nuld:seed"] == "3" and attributes["nuld:integrator"] == "direct"
    assert attributes["nuld:scene"] == "default" and "nuld:version" in attributes
    assert attributes["nuld:lobe_choice"] == "albedo" and stats["lobe_choice"] == "albedo"
    assert attributes["nuld:env_importance"] == "luminance-compensated"
    assert stats["env_importance"] == "luminance-compensated"
    # The paper's configuration, two arguments away: the CLI's flags, the same image.
    paper, paper_stats = nuld.render("default", backend="sobol", spp=2, resolution=(24, 16),
                                     seed=3, integrator="direct", lobe_choice="uniform",
                                     env_importance="luminance", stats=True)
    assert paper_stats["lobe_choice"] == "uniform" and not np.array_equal(paper, img)
    assert paper_stats["env_importance"] == "luminance"
    subprocess.run([nuld_bin, "render", "default", "--backend", "sobol", "--spp", "2", "--res",
                    "24x16", "--seed", "3", "--integrator", "direct", "--lobe-choice", "uniform",
                    "--env-importance", "luminance", "-q", "-o", exr],
                   check=True, capture_output=True)
    assert np.array_equal(nuld.read_image(exr), paper)
    attributes = nuld.read_image_attributes(exr)
    assert attributes["nuld:lobe_choice"] == "uniform"
    assert attributes["nuld:env_importance"] == "luminance"


def test_lobe_options_and_resolution_scale_are_the_clis(tmp_path, nuld_bin):
    # The CLI's --res-scale and --lobe-* options, as keyword arguments: the same image.
    img = nuld.render("default", backend="sobol-tabulated", spp=2, resolution_scale=0.1,
                      seed=3, integrator="direct", lobe_routes="table", lobe_defensive=0.25,
                      lobe_bounces=0)
    exr = str(tmp_path / "lobes.exr")
    subprocess.run([nuld_bin, "render", "default", "--backend", "sobol-tabulated", "--spp", "2",
                    "--res-scale", "0.1", "--seed", "3", "--integrator", "direct",
                    "--lobe-routes", "table", "--lobe-defensive", "0.25", "--lobe-bounces", "0",
                    "-q", "-o", exr], check=True, capture_output=True)
    assert np.array_equal(nuld.read_image(exr), img)
    assert not np.array_equal(img, nuld.render("default", backend="sobol-tabulated", spp=2,
                                               resolution_scale=0.1, seed=3,
                                               integrator="direct"))
    attributes = nuld.read_image_attributes(exr)
    assert attributes["nuld:lobe_defensive"] == "0.25" and attributes["nuld:lobe_bounces"] == "0"


def test_compare_and_image_files(tmp_path):
    ref = nuld.render("default", spp=4, resolution=(12, 8), seed=1)
    img = nuld.render("default", spp=1, resolution=(12, 8), seed=1)
    assert nuld.compare(ref, ref)["mse"] == 0
    e = nuld.compare(img, ref)
    assert e["mse"] > 0 and e["relmse"] > 0
    assert 0 < e["mse_winsorized"] <= e["mse"] and 0 < e["top_share"] < 1
    path = str(tmp_path / "x.exr")
    nuld.write_image(path, img)
    assert np.array_equal(nuld.read_image(path), img)
    with pytest.raises(ValueError, match="differ in size"):
        nuld.compare(img, ref[:4])


def test_flip_is_the_clis(tmp_path, nuld_bin):
    # HDR-FLIP of two renders: 0 against itself, the CLI's mean, a map in [0, 1].
    ref = nuld.render("default", spp=16, resolution=(24, 16), seed=1)
    img = nuld.render("default", spp=1, resolution=(24, 16), seed=2)
    assert nuld.flip(ref, ref)["mean"] == 0
    f = nuld.flip(img, ref)
    assert f["map"].shape == (16, 24) and 0 <= f["map"].min() and f["map"].max() <= 1
    assert f["mean"] == pytest.approx(float(f["map"].mean()), rel=1e-5) and f["mean"] > 0
    assert len(f["exposures"]) == 3
    a, b = str(tmp_path / "a.exr"), str(tmp_path / "b.exr")
    nuld.write_image(a, img)
    nuld.write_image(b, ref)
    out = subprocess.run([nuld_bin, "compare", a, b], check=True, capture_output=True,
                         text=True).stdout
    cli = float(re.search(r"^flip (\S+)$", out, re.M).group(1))
    assert cli == pytest.approx(f["mean"], rel=1e-7)
    ldr = nuld.flip(np.clip(img, 0, 1), np.clip(ref, 0, 1), display=True)
    assert 0 < ldr["mean"] < 1 and "exposures" not in ldr
    with pytest.raises(ValueError, match="flip: monitor_distance"):
        nuld.flip(img, ref, monitor_distance=float("nan"))


def test_bad_render_arguments():
    with pytest.raises(ValueError, match="no_such_backend"):
        nuld.render("default", backend="no_such_backend", resolution=(4, 4))
    with pytest.raises(ValueError, match="integrator"):
        nuld.render("default", integrator="photon", resolution=(4, 4))
    with pytest.raises(ValueError, match="spp"):
        nuld.render("default", spp=0)
    with pytest.raises(ValueError, match=r"render: max_depth: expected a whole number from 1 to 1000 \(got 0\)"):
        nuld.render("default", max_depth=0, resolution=(4, 4))
    with pytest.raises(ValueError, match="lobe_mix"):
        nuld.render("default", lobe_mix=1.5, resolution=(4, 4))
    with pytest.raises(ValueError, match=r"render: lobe_defensive: expected a number in \[0, 1\]"):
        nuld.render("default", lobe_defensive=2.0, resolution=(4, 4))
    with pytest.raises(ValueError, match="render: lobe_bounces: expected a whole number"):
        nuld.render("default", lobe_bounces=-1, resolution=(4, 4))
    with pytest.raises(ValueError, match=r"render: resolution_scale: expected a factor in \(0, 16\]"):
        nuld.render("default", resolution_scale=0.0)
    with pytest.raises(ValueError, match="render: resolution_scale: not with resolution"):
        nuld.render("default", resolution_scale=0.5, resolution=(4, 4))
    with pytest.raises(ValueError, match="unknown lobe routing 'sometimes'"):
        nuld.render("default", lobe_routes="sometimes", resolution=(4, 4))
    with pytest.raises(ValueError, match="unknown lobe choice 'random'"):
        nuld.render("default", lobe_choice="random", resolution=(4, 4))
    with pytest.raises(ValueError, match="unknown importance 'sun'"):
        nuld.render("default", env_importance="sun", resolution=(4, 4))
    with pytest.raises(RuntimeError, match="missing.json"):
        nuld.render("missing.json")


def test_study_words_render_with_their_sets_and_say_what_they_served(tmp_path, monkeypatch):
    # The study's optimized-both makes its sets into the set cache, then a
    # second render finds them; the stats say per pair what they served.
    monkeypatch.setenv("NULD_CACHE", str(tmp_path / "cache"))
    kw = dict(backend="optimized-both", spp=4, resolution=(16, 12), stats=True, seed=3,
              opt_instances=2, opt_epochs=5, opt_lobe_epochs=5)
    img, first = nuld.render("default", **kw)
    again, second = nuld.render("default", **kw)
    assert first["backend"] == "optimized-both" and first["sets_made"] > 0
    assert second["sets_made"] == 0 and second["sets_cached"] == first["sets_made"]
    # one setup time, the sets' making included, as the studies report it
    assert "sets_seconds" not in first and first["setup_seconds"] > second["setup_seconds"]
    assert first["served_light"] > 0 and first["served_bsdf"] > 0
    assert np.array_equal(img, again)


def test_one_seed_default_makes_the_sets_once_across_commands(tmp_path, monkeypatch, nuld_bin):
    # nuld bank, then a study, then nuld render, then nuld.render, none given
    # a seed: the first makes the map's sets, the other three find them.
    monkeypatch.setenv("NULD_CACHE", str(tmp_path / "cache"))
    opts = ["--opt-instances", "2", "--opt-epochs", "4"]
    bank = subprocess.run([nuld_bin, "bank", "default", "--backend", "optimized", "--spp", "4",
                           "-q"] + opts, capture_output=True, text=True, check=True)
    assert re.search(r"^4 +light +made ", bank.stdout, re.M), bank.stdout
    (made,) = (tmp_path / "cache" / "sets").glob("*.ptsb")
    written = made.stat().st_mtime_ns
    study = subprocess.run([nuld_bin, "study", "render", "default", "--res", "8x6", "--spp", "4",
                            "--reference-spp", "8", "--repeats", "2", "--backends",
                            "sobol,optimized", "--no-report", "-q", "-o",
                            str(tmp_path / "study")] + opts,
                           capture_output=True, text=True, check=True)
    assert re.search(r"^optimized +4 ", study.stdout, re.M), study.stdout
    render = subprocess.run([nuld_bin, "render", "default", "--backend", "optimized", "--spp",
                             "4", "--res", "8", "-q", "-o", str(tmp_path / "r.exr")] + opts,
                            capture_output=True, text=True, check=True)
    assert "its 1 sets came from the set cache" in render.stderr, render.stderr
    _, stats = nuld.render("default", backend="optimized", spp=4, resolution=(8, 5), stats=True,
                           opt_instances=2, opt_epochs=4)
    assert stats["sets_made"] == 0 and stats["sets_cached"] == 1
    assert list((tmp_path / "cache" / "sets").glob("*.ptsb")) == [made]
    assert made.stat().st_mtime_ns == written  # found three times, never made again


def test_backend_notes_come_with_the_stats(tmp_path, monkeypatch):
    # The shipped model's banks pass none of the default scene's tables: the
    # stats carry the note nuld render prints; sobol has none.
    monkeypatch.setenv("NULD_CACHE", str(tmp_path / "cache"))
    _, neural = nuld.render("default", backend="neural", spp=16, resolution=(24, 16),
                            integrator="direct", stats=True)
    assert "lobe tables sampled Owen-Sobol through the table" in neural["note"]
    _, sobol = nuld.render("default", backend="sobol", spp=16, resolution=(24, 16), stats=True)
    assert "note" not in sobol


def test_threads_limit_the_cores_and_change_no_pixel():
    one = nuld.render("default", spp=4, resolution=(16, 12), seed=2, threads=1)
    every = nuld.render("default", spp=4, resolution=(16, 12), seed=2)
    assert np.array_equal(one, every)
    with pytest.raises(ValueError, match=r"render: threads: expected a whole number >= 1 \(got 0\)"):
        nuld.render("default", threads=0)


def test_a_reference_comes_from_the_cache_the_cli_fills(tmp_path, monkeypatch, nuld_bin):
    # nuld render --reference makes it; nuld.render(reference=True) with the
    # same scene and settings finds it, pixel for pixel, with its own noise.
    monkeypatch.setenv("NULD_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("NULD_REFERENCE_CACHE", raising=False)
    out = tmp_path / "ref.exr"
    subprocess.run([nuld_bin, "render", "default", "--reference", "--spp", "16", "--res", "12x8",
                    "--integrator", "direct", "-q", "-o", str(out)], check=True,
                   capture_output=True)
    img, made = nuld.render("default", reference=True, spp=16, resolution=(12, 8),
                            integrator="direct", stats=True)
    assert made["cache"] == "found" and made["seconds"] == 0 and made["made_seconds"] > 0
    assert made["variance"] > 0 and made["spp"] == 16
    assert np.array_equal(img, nuld.read_image(str(out)))
    # Another seed is another reference, rendered now.
    _, other = nuld.render("default", reference=True, spp=16, resolution=(12, 8),
                           integrator="direct", seed=5, stats=True)
    assert other["cache"] == "rendered" and other["entry"] != made["entry"]
    with pytest.raises(ValueError, match="classic backend"):
        nuld.render("default", reference=True, backend="optimized", resolution=(8, 6))
    with pytest.raises(ValueError, match="opt_epochs"):
        nuld.render("default", reference=True, opt_epochs=3, resolution=(8, 6))


def test_the_cornell_box_renders_as_the_cli_renders_it(tmp_path, nuld_bin):
    # An area-lit scene without files: finite, lit, and the CLI's image bit for bit.
    img = nuld.render("cornell", backend="sobol", spp=4, resolution=(16, 16), seed=2)
    assert img.shape == (16, 16, 3) and np.all(np.isfinite(img)) and img.mean() > 0
    exr = str(tmp_path / "c.exr")
    subprocess.run([nuld_bin, "render", "cornell", "--backend", "sobol", "--spp", "4", "--res",
                    "16x16", "--seed", "2", "-q", "-o", exr], check=True, capture_output=True)
    assert np.array_equal(nuld.read_image(exr), img)
    assert nuld.read_image_attributes(exr)["nuld:env_importance"] == "none"


def test_a_gltf_scene_renders_as_the_cli_renders_it(tmp_path, nuld_bin):
    # The project's own glTF scene (tools/gltf/make_test_scene.py): the same
    # pixels from Python and from the CLI, and the CLI's note of what is unused.
    script = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "gltf",
                          "make_test_scene.py")
    scene = str(tmp_path / "scene.glb")
    subprocess.run(["/usr/bin/python3", script, scene], check=True)
    img = nuld.render(scene, backend="sobol", spp=4, resolution=(24, 16), seed=3)
    assert img.shape == (16, 24, 3) and np.all(np.isfinite(img)) and img.mean() > 0
    exr = str(tmp_path / "g.exr")
    run = subprocess.run([nuld_bin, "render", scene, "--backend", "sobol", "--spp", "4", "--res",
                          "24x16", "--seed", "3", "-o", exr], check=True, capture_output=True,
                         text=True)
    assert np.array_equal(nuld.read_image(exr), img)
    assert "not used by nuld: " in run.stderr and "normal textures (1)" in run.stderr
