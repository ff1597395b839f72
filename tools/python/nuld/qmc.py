"""scipy.stats.qmc engines over nuld's point sets (tools/python/README.md,
"scipy.stats.qmc").

An optimized or neural set is a finite bank of K sets of N points, not an
extensible sequence. The engines therefore serve the bank's points as one
stream: random(n) returns the next n points, so random(N) called K times
returns the K sets in order; reset() starts the stream again (the same
points: a bank is fixed once made) and fast_forward(n) skips n points.
Asking for more points than the bank holds raises ValueError. Points are
in [0, 1)^2 but follow the bank's target, which is uniform only for
uniform banks; scipy's discrepancies measure against the uniform density.
"""

import numpy as np
from scipy.stats import qmc

from . import _nuld


class PointSetEngine(qmc.QMCEngine):
    """A QMCEngine over a bank: an (N, 2) or (K, N, 2) array, or a
    point-set file (text or binary) by path."""

    def __init__(self, points, *, seed=None):
        metadata = {}
        if isinstance(points, str):
            points, metadata = _nuld.read_points(points)
        bank = np.asarray(points, dtype=float)
        if bank.ndim == 2:
            bank = bank[None]
        if bank.ndim != 3 or bank.shape[2] != 2 or bank.shape[1] == 0:
            raise ValueError("PointSetEngine: expected points of shape (N, 2) or (K, N, 2), got %s"
                             % (np.shape(points),))
        super().__init__(d=2, seed=seed)
        self.bank = bank
        self.metadata = dict(metadata)
        self._stream = bank.reshape(-1, 2)

    @property
    def n(self):
        """Points per set."""
        return self.bank.shape[1]

    def _random(self, n=1, *, workers=1):
        start = self.num_generated
        if start + n > len(self._stream):
            raise ValueError("PointSetEngine: %d points asked after %d, but the bank holds %d "
                             "(%d sets of %d)" % (n, start, len(self._stream), len(self.bank),
                                                  self.n))
        return self._stream[start:start + n].copy()

    def reset(self):
        super().__init__(d=2, seed=self.rng_seed)
        return self

    def fast_forward(self, n):
        if self.num_generated + n > len(self._stream):
            raise ValueError("PointSetEngine: cannot skip %d points: %d of %d are left"
                             % (n, len(self._stream) - self.num_generated, len(self._stream)))
        self.num_generated += n
        return self


class OptimizedEngine(PointSetEngine):
    """K sets of N points optimized for `target` (nuld.optimize with the
    same settings), served as a PointSetEngine. seed seeds the optimizer's
    Sobol starts (an int)."""

    def __init__(self, target="uniform", n=64, instances=1, *, seed=0, preset=None,
                 progress=None, **settings):
        from . import optimize
        self.target = target if isinstance(target, _nuld.Target) else _nuld.Target(target)
        points = optimize(self.target, n, instances, preset=preset, progress=progress, seed=seed,
                          **settings)
        super().__init__(points, seed=seed)


class NeuralEngine(PointSetEngine):
    """K sets a trained model (nuld train) generates from offsets drawn with
    `seed` (an int), at `gamma` for a model of a target family."""

    def __init__(self, model, instances=1, *, seed=0, gamma=(), n=None):
        points, self.target_spec = _nuld.generate_neural(model, instances, seed, list(gamma), n)
        super().__init__(points, seed=seed)
