"""nuld from Python: non-uniform low-discrepancy point sets, their optimizer
and a path tracer to compare them in (tools/python/README.md).

Arrays are numpy: a point set is (N, 2), a bank of K sets (K, N, 2), an image
(H, W, 3) float32 with row 0 at the top. Errors are ValueError (bad input:
points not finite or outside the unit square, as the CLI's readers refuse
them, negative counts, values out of range), TypeError (a wrong type, a
fractional count, None where a value is needed), both naming the function
and the argument, or RuntimeError (files, resources) with the CLI's messages.
"""

from . import _nuld, qmc  # noqa: F401 (nuld.qmc after `import nuld`, as scipy.stats.qmc)
from ._nuld import (  # noqa: F401 (re-exported)
    Target,
    compare,
    discrepancy,
    generate_neural,
    read_image,
    read_image_attributes,
    read_points,
    render,
    sequence,
    write_image,
    write_points,
)
from .progress import TextProgress

__version__ = _nuld.__version__

__all__ = [
    "Target", "TextProgress", "__version__", "compare", "discrepancy", "generate_neural", "optimize",
    "qmc", "read_image", "read_image_attributes", "read_points", "render", "sequence",
    "write_image", "write_points",
]


def optimize(target, n, instances=1, preset=None, progress=None, **settings):
    """Optimizes `instances` sets of `n` points for `target` (a Target or a
    SPEC string), as `nuld optimize`: the preset's settings (default: the
    target's own preset), then any of epochs, boxes, box_kind, mc_samples,
    mapping, objective, lr=(start, end), alpha=(start, end), ramp_fraction,
    cutoff, seed, union_weight, union_group, nested (nested sets: every
    power-of-2 prefix from this size on is optimized as a set too), nested_power.

    progress: None, True (a text bar on stderr with ETA and loss) or a
    callable taking a dict (epoch, epochs, loss, alpha, lr) after each epoch;
    returning False stops there. Ctrl-C raises KeyboardInterrupt.
    Returns a (K, N, 2) array."""
    if isinstance(target, str):
        target = Target(target)
    if progress is True:
        progress = TextProgress("optimize")
    try:
        return _nuld.optimize(target, n, instances, preset, progress, **settings)
    finally:
        if isinstance(progress, TextProgress):
            progress.close()
