"""nuld from Python: non-uniform low-discrepancy point sets, their optimizer
and a path tracer to compare them in (tools/python/README.md).

Arrays are numpy: a point set is (N, 2), a bank of K sets (K, N, 2), an image
(H, W, 3) float32 with row 0 at the top. Errors are ValueError (bad input:
points not finite or outside the unit square, as the CLI's readers refuse
them, negative counts, values out of range, an argument that does not apply,
a size this machine cannot hold, refused before anything is allocated),
TypeError (a wrong type, a fractional count, None where a value is needed, an
unknown keyword), all naming the function and the argument, RuntimeError
(files, resources) with the CLI's messages, or MemoryError (an allocation
that failed all the same), named by the function.
"""

from . import _nuld, qmc  # noqa: F401 (nuld.qmc after `import nuld`, as scipy.stats.qmc)
from ._nuld import (  # noqa: F401 (re-exported)
    Target,
    compare,
    discrepancy,
    flip,
    generate_neural,
    mean_and_error,
    optimize,
    ratio_of_means,
    read_image,
    read_image_attributes,
    read_points,
    render,
    sequence,
    write_image,
    write_points,
)
from .progress import TextProgress
from .studies import StudyTable, study

__version__ = _nuld.__version__

__all__ = [
    "StudyTable", "Target", "TextProgress", "__version__", "compare", "discrepancy",
    "flip", "generate_neural", "mean_and_error", "optimize", "qmc", "ratio_of_means", "read_image",
    "read_image_attributes", "read_points", "render", "sequence", "study", "write_image",
    "write_points",
]
