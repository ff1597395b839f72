# The Python twin of the CLI's option sweep (tests/tools/option_sweep_test.sh):
# every public function, constructor and engine method, each argument given
# each bad input that applies to its kind (NaN, Inf, out of the domain, a
# wrong shape, a complex or bool array, negative, fractional, a seed past
# 2^64 - 1, a wrong type, None where a value is needed), must raise
# ValueError or TypeError in the module's own words: the message starts with
# the function's name and names the argument, and no pybind11, C++ library
# or Python internals reach the user. Then the classes a sweep of one
# argument cannot reach: unknown keywords, images compared across channel
# counts, sizes the machine cannot hold (refused in under a second), the
# CLI's rules of which arguments apply, scipy's engine contract at its edges,
# and write_points by extension.
import subprocess
import time

import numpy as np

import nuld
from refusals import foreign, refusal

NAN = np.array([[0.5, np.nan], [0.2, 0.3]])
INF = np.array([[0.5, 0.5], [np.inf, 0.3]])
IMAGE = np.zeros((2, 2, 3), dtype=np.float32)


def image_with(value):
    image = IMAGE.copy()
    image[1, 0, 2] = value
    return image


# The bad values each kind of argument is given, by input class.
BAD = {
    "points": {"nan": NAN, "inf": INF, "out-of-domain": np.array([[0.5, 1.5]]),
               "wrong shape": np.zeros((3, 3)), "complex": np.array([[0.5 + 0.5j, 0.25]]),
               "bool": np.array([[True, False], [False, True]]), "wrong type": {"x": 0.5},
               "none": None},
    # An image whose values must be finite (a reference, an image written).
    "image": {"nan": image_with(np.nan), "inf": image_with(np.inf),
              "wrong shape": np.zeros((2, 2, 7)), "empty": np.zeros((0, 2, 3)),
              "complex": IMAGE.astype(complex), "bool": IMAGE.astype(bool), "wrong type": "image",
              "none": None},
    "count": {"negative": -1, "fractional": 2.5, "wrong type": "4", "none": None},
    "seed": {"negative": -1, "fractional": 2.5, "past 2^64 - 1": 2**64, "wrong type": "4"},
    "number": {"nan": np.nan, "inf": np.inf, "wrong type": "0.5"},
    "pair": {"nan": (np.nan, 0.5), "wrong shape": (0.1, 0.2, 0.3), "wrong type": "lo",
             "none": None},
    "resolution": {"negative": (-8, 8), "fractional": (8.5, 8), "wrong shape": (8, 8, 8),
                   "wrong type": 64},
    "text": {"wrong type": 3, "none": None},
    "flag": {"wrong type": "yes", "none": None},
    "target": {"wrong type": 3},
    "callable": {"wrong type": 3},
    "numbers": {"nan": [np.nan], "wrong type": "x"},
    "metadata": {"wrong type": ["a"]},
}
# The image compare measures may hold non-finite pixels (counted, as nuld
# compare counts them); both of compare's images must have the other's
# channels (a grey one against the colour one here).
BAD["test image"] = {c: v for c, v in BAD["image"].items() if c not in ("nan", "inf")}
BAD["test image"]["channels"] = np.zeros((2, 2), dtype=np.float32)
BAD["image"]["channels"] = np.zeros((2, 2), dtype=np.float32)
# Optional arguments take None; these kinds are the optional versions.
OPTIONAL = {"count?": "count", "seed?": "seed", "number?": "number", "text?": "text",
            "target?": "target", "pair?": "pair", "resolution?": "resolution",
            "callable?": "callable"}


def kinds(kind, name):
    base = OPTIONAL.get(kind, kind)
    # A grey image is an image write_image writes.
    return {c: v for c, v in BAD[base].items()
            if not (kind in OPTIONAL and c == "none") and
            not (name == "write_image" and c == "channels")}


def engines(model):
    from nuld import qmc
    return {
        "nuld.qmc.Sobol": lambda: qmc.Sobol(d=2, seed=1),
        "nuld.qmc.Halton": lambda: qmc.Halton(d=2, seed=1),
        "nuld.qmc.PointSetEngine": lambda: qmc.PointSetEngine(nuld.sequence(4, instances=2)),
        "nuld.qmc.OptimizedEngine": lambda: qmc.OptimizedEngine(n=4, epochs=2),
        "nuld.qmc.NeuralEngine": lambda: qmc.NeuralEngine(model, instances=2),
    }


def entries(model, tmp):
    """(name, call(**arguments), valid arguments, {argument: kind})."""
    from nuld import qmc
    pts = nuld.sequence(4)
    out = str(tmp / "out.txt")
    image = np.zeros((2, 2, 3), dtype=np.float32)
    u = nuld.Target("uniform")
    rows = [
        ("Target", nuld.Target, dict(spec="uniform"), {"spec": "text"}),
        ("Target.pdf", u.pdf, dict(points=pts), {"points": "points"}),
        ("Target.mass", u.mass, dict(lo=(0, 0), hi=(1, 1)), {"lo": "pair", "hi": "pair"}),
        ("Target.invert", u.invert, dict(u=pts), {"u": "points"}),
        ("sequence", nuld.sequence,
         dict(n=4, kind="sobol", scramble="owen", seed=0, instances=None, target=None),
         {"n": "count", "kind": "text", "scramble": "text?", "seed": "seed",
          "instances": "count?", "target": "target?"}),
        ("optimize", nuld.optimize, dict(target="uniform", n=4, instances=1, preset=None,
                                               progress=None, epochs=2, seed=0, lr=(0.1, 0.01),
                                               union_weight=0.0),
         {"target": "target", "n": "count", "instances": "count", "preset": "text?",
          "progress": "callable", "epochs": "count", "seed": "seed", "lr": "pair",
          "union_weight": "number"}),
        ("discrepancy", nuld.discrepancy, dict(points=pts, metric="l2star", target=None, grid=16),
         {"points": "points", "metric": "text", "target": "target?", "grid": "count"}),
        ("read_points", nuld.read_points, dict(path=out), {"path": "text"}),
        ("write_points", nuld.write_points, dict(path=out, points=pts, metadata=None),
         {"path": "text", "points": "points", "metadata": "metadata"}),
        ("generate_neural", nuld.generate_neural,
         dict(model=model, instances=1, seed=0, gamma=(), n=None),
         {"model": "text", "instances": "count", "seed": "seed", "gamma": "numbers",
          "n": "count?"}),
        ("render", nuld.render,
         dict(scene="default", backend="sobol", spp=1, resolution=(4, 4), integrator=None,
              max_depth=None, seed=None, assets=None, lobe_mix=None, stats=False,
              opt_instances=None, opt_epochs=None, opt_lobe_epochs=None, threads=None,
              lobe_choice="albedo", env_importance=None, resolution_scale=1.0, lobe_routes=None,
              lobe_defensive=None, lobe_bounces=None, opt_nested=False, opt_objective=None,
              opt_union_weight=None, progress=None),
         {"scene": "text", "backend": "text?", "spp": "count?", "resolution": "resolution?",
          "integrator": "text?", "max_depth": "count?", "seed": "seed?", "assets": "text?",
          "lobe_mix": "number?", "stats": "flag", "opt_instances": "count?",
          "opt_epochs": "count?", "opt_lobe_epochs": "count?", "threads": "count?",
          "lobe_choice": "text", "env_importance": "text?", "resolution_scale": "number",
          "lobe_routes": "text?", "lobe_defensive": "number?", "lobe_bounces": "count?",
          "opt_nested": "flag", "opt_objective": "text?", "opt_union_weight": "number?",
          "progress": "callable?"}),
        ("compare", nuld.compare, dict(image=image, reference=image),
         {"image": "test image", "reference": "image"}),
        ("read_image", nuld.read_image, dict(path=out), {"path": "text"}),
        ("read_image_attributes", nuld.read_image_attributes, dict(path=out), {"path": "text"}),
        ("write_image", nuld.write_image, dict(path=str(tmp / "i.pfm"), image=image),
         {"path": "text", "image": "image"}),
        ("nuld.qmc.Sobol", qmc.Sobol, dict(scramble=True, seed=1),
         {"scramble": "flag", "seed": "seed?"}),
        ("nuld.qmc.Halton", qmc.Halton, dict(scramble=True, seed=1),
         {"scramble": "flag", "seed": "seed?"}),
        ("nuld.qmc.PointSetEngine", qmc.PointSetEngine, dict(points=pts, seed=1),
         {"points": "points", "seed": "seed?"}),
        ("nuld.qmc.OptimizedEngine", qmc.OptimizedEngine,
         dict(target="uniform", n=4, instances=1, epochs=2, seed=1),
         {"target": "target", "n": "count?", "instances": "count", "seed": "seed?"}),
        # NeuralEngine's model and gamma are read by generate_neural, and
        # refused in the engine's name.
        ("nuld.qmc.NeuralEngine", qmc.NeuralEngine,
         dict(model=model, instances=1, n=None, gamma=(), seed=1),
         {"model": "text", "instances": "count", "n": "count?", "gamma": "numbers",
          "seed": "seed?"}),
    ]
    for name, make in engines(model).items():
        rows += [(name + ".random", lambda make=make, **a: make().random(**a), dict(n=2),
                  {"n": "count"}),
                 (name + ".random_base2", lambda make=make, **a: make().random_base2(**a),
                  dict(m=1), {"m": "count"}),
                 (name + ".fast_forward", lambda make=make, **a: make().fast_forward(**a),
                  dict(n=2), {"n": "count"})]
    return rows


def sweep(model, tmp):
    for name, call, valid, args in entries(model, tmp):
        for arg, kind in args.items():
            for bad_class, value in kinds(kind, name).items():
                yield name, call, dict(valid, **{arg: value}), arg, bad_class


def test_every_entry_point_refuses_every_bad_input_in_its_own_words(model, tmp_path):
    refused, failures, classes = 0, [], set()
    for name, call, arguments, arg, bad_class in sweep(model, tmp_path):
        classes.add(bad_class)
        case = "%s(%s=<%s>)" % (name, arg, bad_class)
        try:
            result = call(**arguments)
        except (ValueError, TypeError) as e:
            text = str(e)
            if not text.startswith(name + ":") or arg not in text:
                failures.append("%s: not in the module's words: %s" % (case, text))
            elif foreign(text):
                failures.append("%s: foreign text: %s" % (case, text))
            else:
                refused += 1
            continue
        except Exception as e:  # noqa: BLE001 (any other exception is a failure)
            failures.append("%s: %s: %s" % (case, type(e).__name__, e))
            continue
        failures.append("%s: returned %r" % (case, result))
    assert not failures, "\n".join(failures)
    assert classes == {"nan", "inf", "out-of-domain", "wrong shape", "empty", "channels",
                       "complex", "bool", "negative", "fractional", "past 2^64 - 1",
                       "wrong type", "none"}
    assert refused > 200


def test_import_nuld_exposes_qmc():
    import importlib
    import sys
    for mod in [m for m in sys.modules if m == "nuld" or m.startswith("nuld.")]:
        del sys.modules[mod]
    fresh = importlib.import_module("nuld")
    assert fresh.qmc.Sobol(d=2, seed=1).random(4).shape == (4, 2)


def misspelt(name):
    """A typo of `name` close enough for a 'did you mean'."""
    return name[:-1] + name[-1] * 2 if len(name) > 3 else name + "x"


def test_unknown_keywords_are_refused_with_the_closest_name(model, tmp_path):
    # The issue's two, word for word.
    text = refusal(lambda: nuld.render("default", resolutoin=(4, 4)), TypeError, "render")
    assert text == "render: unknown keyword 'resolutoin'; did you mean 'resolution'?"
    text = refusal(lambda: nuld.sequence(16, instancez=2), TypeError, "sequence")
    assert text == "sequence: unknown keyword 'instancez'; did you mean 'instances'?"
    # Every public function, constructor and engine method: each argument
    # misspelt, and a word close to none of them.
    checked = 0
    for name, call, valid, args in entries(model, tmp_path):
        for arg in args:
            typo = misspelt(arg)
            arguments = {k: v for k, v in valid.items() if k != arg}
            arguments[typo] = valid[arg]
            # A one-letter name has no close misspelling: the names are listed.
            refusal(lambda: call(**arguments), TypeError, name, "unknown keyword '%s'%s" % (
                typo, "; did you mean '%s'?" % arg if len(arg) > 1 else " (expected "))
            checked += 1
        refusal(lambda: call(**dict(valid, zzzzzz=1)), TypeError, name,
                "unknown keyword 'zzzzzz' (expected ")
    assert checked > 80
    # optimize's settings are keywords too, and so are OptimizedEngine's.
    refusal(lambda: nuld.optimize("uniform", 4, epoch=2), TypeError, "optimize",
            "did you mean 'epochs'?")
    refusal(lambda: nuld.qmc.OptimizedEngine(d=2, epoch=2), TypeError,
            "nuld.qmc.OptimizedEngine", "did you mean 'epochs'?")
    refusal(lambda: nuld.qmc.Sobol(d=2, seed=1).reset(1), TypeError, "nuld.qmc.Sobol.reset",
            "positional")
    # The other ways a call goes wrong, in the same words.
    refusal(lambda: nuld.sequence(), TypeError, "sequence", "missing argument 'n'")
    refusal(lambda: nuld.sequence(4, n=4), TypeError, "sequence", "'n' given twice")
    refusal(lambda: nuld.read_points("a", "b"), TypeError, "read_points",
            "at most 1 positional argument (got 2)")
    refusal(lambda: nuld.Target(), TypeError, "Target", "missing argument 'spec'")
    refusal(lambda: nuld.Target("uniform").pdf(), TypeError, "Target.pdf", "'points'")


def test_help_shows_each_functions_own_signature():
    import inspect
    assert str(inspect.signature(nuld.sequence)) == (
        "(n, kind='sobol', scramble=None, seed=1, instances=None, target=None)")
    assert "opt_union_weight=None" in str(inspect.signature(nuld.render))
    assert str(inspect.signature(nuld.optimize)).endswith("progress=None, **settings)")
    assert nuld.sequence.__doc__.startswith("N points of a sequence")


def test_images_are_checked_as_nuld_compare_checks_them(tmp_path):
    image = np.full((4, 6, 3), 0.5, dtype=np.float32)
    grey = np.full((4, 6), 0.5, dtype=np.float32)
    refusal(lambda: nuld.compare(image, grey), ValueError, "compare",
            "images differ in channels: 3 vs reference 1")
    refusal(lambda: nuld.compare(grey, image), ValueError, "compare", "channels")
    refusal(lambda: nuld.compare(image, image[:, :, :2].copy()), ValueError, "compare",
            "channels")
    refusal(lambda: nuld.compare(image, image[:2]), ValueError, "compare", "differ in size")
    for bad in (np.nan, np.inf, -np.inf):
        reference = image.copy()
        reference[2, 1, 0] = bad
        refusal(lambda: nuld.compare(image, reference), ValueError, "compare",
                "reference: pixel (1, 2) channel 0 is not a finite number")
        refusal(lambda: nuld.write_image(str(tmp_path / "x.exr"), reference), ValueError,
                "write_image", "image: pixel (1, 2) channel 0 is not a finite number")
        # The image under test may hold them: counted and left out, as nuld
        # compare does.
        assert nuld.compare(reference, image)["nonfinite_pixels"] == 1
    assert not (tmp_path / "x.exr").exists()
    for bad in (image.astype(complex), image.astype(bool), image.astype(object)):
        refusal(lambda: nuld.compare(bad, image), TypeError, "compare", "image",
                "real numbers")
    # A grey image is an image: written and read back as one.
    nuld.write_image(str(tmp_path / "grey.exr"), grey)
    assert nuld.read_image(str(tmp_path / "grey.exr")).shape == (4, 6)


def test_the_cli_refuses_images_of_other_channels(tmp_path, nuld_bin):
    nuld.write_image(str(tmp_path / "rgb.exr"), np.full((4, 6, 3), 0.5, dtype=np.float32))
    nuld.write_image(str(tmp_path / "grey.exr"), np.full((4, 6), 0.5, dtype=np.float32))
    run = subprocess.run([nuld_bin, "compare", str(tmp_path / "rgb.exr"),
                          str(tmp_path / "grey.exr")], capture_output=True, text=True)
    assert run.returncode == 1 and "images differ in channels: 3 vs reference 1" in run.stderr


def test_only_real_numeric_arrays_are_points(tmp_path):
    pts = np.array([[0.25, 0.5], [0.75, 0.125]])
    u = nuld.Target("uniform")
    calls = {"discrepancy": lambda p: nuld.discrepancy(p), "Target.pdf": u.pdf,
             "Target.invert": u.invert,
             "write_points": lambda p: nuld.write_points(str(tmp_path / "p.txt"), p),
             "nuld.qmc.PointSetEngine": nuld.qmc.PointSetEngine}
    for name, call in calls.items():
        for bad, dtype in ((pts + 0.5j, "complex128"), (pts > 0.3, "bool"),
                           (pts.astype(object), "object"), (pts.astype(str), "<U")):
            refusal(lambda: call(bad), TypeError, name, "real numbers", "got an array of " + dtype)
        # Integer and every floating dtype are numbers.
        for good in (pts.astype(np.float32), pts.astype(np.float16), np.zeros((2, 2), np.int64),
                     np.zeros((2, 2), np.uint8), pts.tolist()):
            call(good)
    assert not (tmp_path / "p.npy").exists()


def test_oversized_counts_are_refused_before_memory_is_taken(model):
    cases = [
        ("sequence", lambda: nuld.sequence(10**12), "n: 1000000000000 points"),
        ("sequence", lambda: nuld.sequence(16, instances=2**40),
         "instances x n: 1099511627776 x 16 points"),
        ("render", lambda: nuld.render("default", resolution=(400000, 400000)),
         "resolution: a 400000 x 400000 render"),
        ("render", lambda: nuld.render("default", resolution=(8, 8), spp=2**40),
         "resolution: a 8 x 8 render at 1099511627776 spp"),
        # The optimizer's count overflowed 64 bits here and crashed.
        ("optimize", lambda: nuld.optimize("uniform", 2**40, instances=2**30, epochs=1),
         "instances x n: 1073741824 x 1099511627776 points"),
        ("nuld.qmc.OptimizedEngine", lambda: nuld.qmc.OptimizedEngine(n=10**12, epochs=1),
         "instances x n: 1 x 1000000000000 points"),
        ("nuld.qmc.OptimizedEngine.random",
         lambda: nuld.qmc.OptimizedEngine(d=2, epochs=1).random(10**12), "n: 1 x 1000000000000"),
        ("generate_neural", lambda: nuld.generate_neural(model, instances=2**40),
         "instances x n: 1099511627776 x 8 points"),
        ("nuld.qmc.Sobol.random", lambda: nuld.qmc.Sobol(d=2, seed=1).random(2**40),
         "n: 1099511627776 points"),
        ("nuld.qmc.Halton.random_base2", lambda: nuld.qmc.Halton(d=2, seed=1).random_base2(50),
         "m: "),
        ("nuld.qmc.NeuralEngine", lambda: nuld.qmc.NeuralEngine(model, instances=2**40),
         "instances x n"),
    ]
    for name, call, words in cases:
        start = time.monotonic()
        text = refusal(call, ValueError, name, words, "needs about", "more than this machine's")
        seconds = time.monotonic() - start
        assert seconds < 1, (name, seconds, text)


def test_the_cli_refuses_a_render_the_machine_cannot_hold_as_python_does(nuld_bin, tmp_path):
    # The renderer's one check (renderMemoryBytes), in each front end's words;
    # --spp past any machine's memory at the CLI's largest resolution.
    start = time.monotonic()
    run = subprocess.run([nuld_bin, "render", "default", "--res", "32768x32768", "--spp",
                          "16777216", "--max-depth", "1000", "-q", "-o", str(tmp_path / "x.exr")],
                         capture_output=True, text=True)
    assert time.monotonic() - start < 1
    assert run.returncode == 2 and "--res: a 32768 x 32768 render at 16777216 spp needs about" \
        in run.stderr, run.stderr
    assert not list(tmp_path.iterdir())


def test_seeds_past_2_to_the_64_are_refused(model):
    top = 2**64 - 1
    assert nuld.sequence(4, seed=top).shape == (4, 2)
    assert nuld.qmc.Sobol(d=2, seed=top).random(4).shape == (4, 2)
    calls = {
        "sequence": lambda s: nuld.sequence(4, seed=s),
        "render": lambda s: nuld.render("default", resolution=(4, 4), spp=1, seed=s),
        "generate_neural": lambda s: nuld.generate_neural(model, seed=s),
        "optimize": lambda s: nuld.optimize("uniform", 4, epochs=1, seed=s),
        "nuld.qmc.Sobol": lambda s: nuld.qmc.Sobol(d=2, seed=s),
        "nuld.qmc.Halton": lambda s: nuld.qmc.Halton(d=2, seed=s),
        "nuld.qmc.OptimizedEngine": lambda s: nuld.qmc.OptimizedEngine(d=2, seed=s),
        "nuld.qmc.PointSetEngine": lambda s: nuld.qmc.PointSetEngine(nuld.sequence(4), seed=s),
        "nuld.qmc.NeuralEngine": lambda s: nuld.qmc.NeuralEngine(d=2, model=model, seed=s),
    }
    for name, call in calls.items():
        for seed in (2**64, 2**70, -(2**64)):
            refusal(lambda: call(seed), ValueError, name, "seed", "2^64 - 1")
