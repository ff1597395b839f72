# The Python twin of the CLI's option sweep (tests/tools/option_sweep_test.sh):
# every public function, constructor and engine method, each argument given
# each bad input that applies to its kind (NaN, Inf, out of the domain, a
# wrong shape, negative, fractional, a wrong type, None where a value is
# needed), must raise ValueError or TypeError in the module's own words:
# the message starts with the function's name and names the argument, and
# no pybind11 or Python internals reach the user.
import subprocess

import numpy as np
import pytest

import nuld

NAN = np.array([[0.5, np.nan], [0.2, 0.3]])
INF = np.array([[0.5, 0.5], [np.inf, 0.3]])

# The bad values each kind of argument is given, by input class.
BAD = {
    "points": {"nan": NAN, "inf": INF, "out-of-domain": np.array([[0.5, 1.5]]),
               "wrong shape": np.zeros((3, 3)), "wrong type": {"x": 0.5}, "none": None},
    "image": {"wrong shape": np.zeros((2, 2, 7)), "wrong type": "image", "none": None},
    "count": {"negative": -1, "fractional": 2.5, "wrong type": "4", "none": None},
    "seed": {"negative": -1, "fractional": 2.5, "wrong type": "4"},
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
# Optional arguments take None; these kinds are the optional versions.
OPTIONAL = {"count?": "count", "seed?": "seed", "number?": "number", "text?": "text",
            "target?": "target", "pair?": "pair", "resolution?": "resolution"}


def kinds(kind):
    base = OPTIONAL.get(kind, kind)
    return {c: v for c, v in BAD[base].items() if not (kind in OPTIONAL and c == "none")}


@pytest.fixture(scope="module")
def model(tmp_path_factory, nuld_bin):
    path = str(tmp_path_factory.mktemp("model") / "tiny.nuldnet")
    subprocess.run([nuld_bin, "train", "--target", "uniform", "--n", "8", "--hidden", "16",
                    "--steps", "2", "-q", "-o", path], check=True, capture_output=True)
    return path


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
         {"n": "count", "kind": "text", "scramble": "text", "seed": "seed",
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
              max_depth=None, seed=None, assets="", lobe_mix=None, stats=False, opt_instances=2,
              opt_epochs=2, opt_lobe_epochs=2, threads=None, lobe_choice="albedo",
              env_importance=None, resolution_scale=1.0, lobe_routes=None,
              lobe_defensive=None, lobe_bounces=None),
         {"scene": "text", "backend": "text?", "spp": "count?", "resolution": "resolution?",
          "integrator": "text?", "max_depth": "count?", "seed": "seed?", "assets": "text",
          "lobe_mix": "number?", "stats": "flag", "opt_instances": "count",
          "opt_epochs": "count", "opt_lobe_epochs": "count", "threads": "count?",
          "lobe_choice": "text", "env_importance": "text?", "resolution_scale": "number",
          "lobe_routes": "text?", "lobe_defensive": "number?", "lobe_bounces": "count?"}),
        ("compare", nuld.compare, dict(image=image, reference=image),
         {"image": "image", "reference": "image"}),
        ("read_image", nuld.read_image, dict(path=out), {"path": "text"}),
        ("read_image_attributes", nuld.read_image_attributes, dict(path=out), {"path": "text"}),
        ("write_image", nuld.write_image, dict(path=str(tmp / "i.pfm"), image=image),
         {"path": "text", "image": "image"}),
        ("nuld.qmc.Sobol", qmc.Sobol, dict(scramble=True), {"scramble": "flag"}),
        ("nuld.qmc.Halton", qmc.Halton, dict(scramble=True), {"scramble": "flag"}),
        ("nuld.qmc.PointSetEngine", qmc.PointSetEngine, dict(points=pts), {"points": "points"}),
        ("nuld.qmc.OptimizedEngine", qmc.OptimizedEngine,
         dict(target="uniform", n=4, instances=1, epochs=2),
         {"target": "target", "n": "count?", "instances": "count"}),
        # NeuralEngine hands its model and gamma to generate_neural.
        ("nuld.qmc.NeuralEngine", qmc.NeuralEngine, dict(model=model, instances=1, n=None),
         {"instances": "count", "n": "count?"}),
    ]
    for name, make in engines(model).items():
        rows += [(name + ".random", lambda make=make, **a: make().random(**a), dict(n=2),
                  {"n": "count"}),
                 (name + ".random_base2", lambda make=make, **a: make().random_base2(**a),
                  dict(m=1), {"m": "count"}),
                 (name + ".fast_forward", lambda make=make, **a: make().fast_forward(**a),
                  dict(n=2), {"n": "count"})]
    return rows


FOREIGN = ("incompatible function arguments", "Unable to cast", "unsupported operand",
           "NoneType", "not supported between", "object cannot be interpreted",
           "PYBIND11", "could not convert", "must be real number")


def sweep(model, tmp):
    for name, call, valid, args in entries(model, tmp):
        for arg, kind in args.items():
            for bad_class, value in kinds(kind).items():
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
            elif any(f in text for f in FOREIGN):
                failures.append("%s: foreign text: %s" % (case, text))
            else:
                refused += 1
            continue
        except Exception as e:  # noqa: BLE001 (any other exception is a failure)
            failures.append("%s: %s: %s" % (case, type(e).__name__, e))
            continue
        failures.append("%s: returned %r" % (case, result))
    assert not failures, "\n".join(failures)
    assert classes == {"nan", "inf", "out-of-domain", "wrong shape", "negative", "fractional",
                       "wrong type", "none"}
    assert refused > 150


def test_import_nuld_exposes_qmc():
    import importlib
    import sys
    for mod in [m for m in sys.modules if m == "nuld" or m.startswith("nuld.")]:
        del sys.modules[mod]
    fresh = importlib.import_module("nuld")
    assert fresh.qmc.Sobol(d=2, seed=1).random(4).shape == (4, 2)
