"""scipy.stats.qmc engines over nuld's point sets (tools/python/README.md,
"scipy.stats.qmc").

An optimized or neural set is a finite bank of K sets of N points, not an
extensible sequence. The engines therefore serve the bank's points as one
stream: random(n) returns the next n points, so random(N) called K times
returns the K sets in order; reset() starts the stream again (the same
points: a bank is fixed once made) and fast_forward(n) skips n points.
Asking for more points than the bank holds raises ValueError. Calls, counts
and points are read as the module's functions read them (_nuld._check_call,
_nuld._count, _nuld._points): an unknown keyword or a bad value raises
TypeError or ValueError naming the engine's method the user called and the
argument, and so does what the module's functions an engine calls refuse.
Points are in [0, 1)^2 but follow the bank's target, which is uniform only
for uniform banks; scipy's discrepancies measure against the uniform density.
"""

import contextlib
import functools
import inspect

import numpy as np
from scipy.stats import qmc

from . import _nuld


def _checked(method=None):
    """The call read as the module's functions read theirs (args.h,
    Signature): an unknown keyword (named with the closest one), too many
    positional arguments, one given twice or a missing one is a TypeError
    naming the engine, or its method, in the module's words. An engine
    taking **settings takes the optimizer's (nuld.optimize's) there."""
    def wrap(f):
        params = list(inspect.signature(f).parameters.values())[1:]
        named = [p for p in params if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
        names = [p.name for p in named]
        required = [p.default is p.empty for p in named]
        positional = sum(p.kind == p.POSITIONAL_OR_KEYWORD for p in named)
        settings = (list(_nuld._optimize_settings)
                    if any(p.kind == p.VAR_KEYWORD for p in params) else [])

        @functools.wraps(f)
        def checked(self, *args, **kwargs):
            _nuld._check_call(self.name + ("." + method if method else ""), names, required,
                              positional, settings, args, kwargs)
            return f(self, *args, **kwargs)
        return checked
    return wrap


@contextlib.contextmanager
def _as(name, argument=None):
    """What a module function the engine calls refuses, named by the
    engine's method the user called (`name`), and by `argument` where the
    engine's argument is not the function's own (random_base2's m)."""
    try:
        yield
    except (ValueError, TypeError, MemoryError, RuntimeError) as e:
        function, sep, rest = str(e).partition(": ")
        if not sep or " " in function or function == name:
            raise  # not a module function's refusal, or named already
        if argument is not None:
            inner, sep, tail = rest.partition(": ")
            if sep and inner.isidentifier():  # the function's argument, not a path
                rest = argument + ": " + tail
        raise type(e)(name + ": " + rest) from None


class _CheckedCounts:
    """random, random_base2, fast_forward and reset with their calls and
    counts read as the module reads them, before scipy's or the engine's own
    code; what they refuse is named by the method called."""

    name = None

    @_checked("random")
    def random(self, n=1, *, workers=1):
        return self._draw(_nuld._count(n, self.name + ".random", "n", 0), "random", "n")

    @_checked("random_base2")
    def random_base2(self, m):
        return self._random_base2(_nuld._count(m, self.name + ".random_base2", "m", 0))

    @_checked("fast_forward")
    def fast_forward(self, n):
        n = _nuld._count(n, self.name + ".fast_forward", "n", 0)
        with _as(self.name + ".fast_forward", "n"):
            return self._fast_forward(n)

    @_checked("reset")
    def reset(self):
        return self._reset()

    def _draw(self, n, method, argument):
        """The next n points, as scipy's QMCEngine.random draws them;
        refusals named by `method`."""
        with _as(self.name + "." + method, argument):
            sample = self._random(n)
        self.num_generated += n
        return sample

    def _random_base2(self, m):
        """2^m points, as scipy's Sobol.random_base2."""
        return self._draw(2**m, "random_base2", "m")


class PointSetEngine(_CheckedCounts, qmc.QMCEngine):
    """A QMCEngine over a bank: an (N, 2) or (K, N, 2) array, or a
    point-set file (text or binary) by path."""

    name = "nuld.qmc.PointSetEngine"

    @_checked()
    def __init__(self, points, *, d=2, seed=None):
        _check_d(d, self.name)
        _seed_int(seed, self.name)  # nuld's reading of the seed, before scipy's
        metadata = {}
        with _as(self.name):
            if isinstance(points, str):
                points, metadata = _nuld.read_points(points)
        bank = _nuld._points(points, self.name, "points")
        qmc.QMCEngine.__init__(self, d=2, seed=seed)
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
            raise ValueError("%s: n: %d points asked after %d, but the bank holds %d (%d sets of "
                             "%d); reset() serves them again, or make the engine with more "
                             "instances" % (self.name, n, start, len(self._stream),
                                            len(self.bank), self.n))
        return self._stream[start:start + n].copy()

    def _reset(self):
        qmc.QMCEngine.__init__(self, d=2, seed=self.rng_seed)
        return self

    def _fast_forward(self, n):
        if self.num_generated + n > len(self._stream):
            raise ValueError("%s: n: cannot skip %d points: %d of %d are left; reset() starts "
                             "the bank again" % (self.name, n, len(self._stream) -
                                                 self.num_generated, len(self._stream)))
        self.num_generated += n
        return self


def _seed_int(seed, engine):
    """scipy's seed conventions as the int nuld's generators take: None
    (fresh entropy), a whole number from 0 to 2^64 - 1, or a numpy Generator
    (one draw)."""
    if seed is None:
        return int(np.random.default_rng().integers(2**63))
    if isinstance(seed, np.random.Generator):
        return int(seed.integers(2**63))
    try:
        return _nuld._seed(seed, engine, "seed")
    except (TypeError, ValueError) as e:
        shown = repr(seed) if len(repr(seed)) <= 40 else repr(seed)[:37] + "..."
        raise type(e)("%s: seed: expected None, a whole number from 0 to 2^64 - 1 or a "
                      "numpy.random.Generator (got %s)" % (engine, shown)) from None


def _check_d(d, engine):
    if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or d != 2:
        raise ValueError("%s: d: nuld's point sets are 2-dimensional; d=%r is not supported (use "
                         "d=2, or scipy's engines for other dimensions)" % (engine, d))


def _warn_partial(engine, n, start, size):
    """Like scipy's warning when Sobol' points are drawn in a count that is
    not a power of 2: a request that is not whole sets loses the sets'
    balance."""
    if n % size or start % size:
        import warnings
        warnings.warn("%s: the points were made as sets of %d; drawing %d from point %d takes "
                      "a partial set, which does not keep their balance properties"
                      % (engine, size, n, start), UserWarning, stacklevel=6)


class OptimizedEngine(PointSetEngine):
    """Sets optimized for `target` (nuld.optimize with the same settings),
    served as a PointSetEngine, constructed as scipy's engines are:
    OptimizedEngine(d=2, seed=...) with seed None, an int or a numpy
    Generator (it seeds the optimizer's Sobol starts).

    With n given, `instances` sets of n points are made at once. Without it
    the engine makes its sets as they are asked for: random(m) optimizes sets
    of m points, and asking past them optimizes `instances` more (the next
    seeds), so the stream does not end. A request that is not whole sets
    warns, as scipy's Sobol does for a count that is not a power of 2.

    The first positional argument may also be the target (the older form
    OptimizedEngine("uniform", n=16))."""

    name = "nuld.qmc.OptimizedEngine"

    @_checked()
    def __init__(self, d=2, *, target="uniform", n=None, instances=1, seed=None, preset=None,
                 progress=None, **settings):
        if isinstance(d, (str, _nuld.Target)):
            target, d = d, 2
        _check_d(d, self.name)
        if not isinstance(target, (str, _nuld.Target)):
            raise TypeError("%s: target: expected a nuld.Target or a SPEC string (got %r)"
                            % (self.name, target))
        with _as(self.name):
            self.target = target if isinstance(target, _nuld.Target) else _nuld.Target(target)
        self._seed = _seed_int(seed, self.name)
        self._instances = _nuld._count(instances, self.name, "instances", 1)
        self._options = dict(preset=preset, progress=progress, **settings)
        self._made = 0  # batches of `instances` sets made so far
        if n is not None:
            points = self._optimize(_nuld._count(n, self.name, "n", 1), self.name)
        else:
            points = np.zeros((0, 1, 2))  # made on the first request
        self._lazy = n is None
        self._init_bank(points, seed)

    def _init_bank(self, points, seed):
        qmc.QMCEngine.__init__(self, d=2, seed=seed)
        self.bank = np.asarray(points, dtype=float)
        self.metadata = {}
        self._stream = self.bank.reshape(-1, 2)

    def _optimize(self, n, name):
        """`instances` more sets of n points (the next seed), refusals named
        by `name`, the method called."""
        with _as(name):
            batch = _nuld.optimize(self.target, n, self._instances,
                                   seed=(self._seed + self._made) % 2**64, **self._options)
        self._made += 1
        return batch

    @property
    def n(self):
        return self.bank.shape[1] if len(self.bank) else None

    def _random(self, n=1, *, workers=1):
        start = self.num_generated
        if self._lazy and n == 0:
            return np.zeros((0, 2))
        if self._lazy:
            if not len(self.bank):
                self.bank = self._optimize(n, self.name + ".random")
            while start + n > len(self.bank) * self.bank.shape[1]:
                self.bank = np.concatenate([self.bank, self._optimize(self.bank.shape[1],
                                                                      self.name + ".random")])
            self._stream = self.bank.reshape(-1, 2)
        _warn_partial(self.name, n, start, self.bank.shape[1])
        return super()._random(n, workers=workers)

    def _fast_forward(self, n):
        if self._lazy and len(self.bank):
            while self.num_generated + n > len(self._stream):
                self.bank = np.concatenate([self.bank, self._optimize(
                    self.bank.shape[1], self.name + ".fast_forward")])
                self._stream = self.bank.reshape(-1, 2)
        return super()._fast_forward(n)


class _SequenceEngine(_CheckedCounts, qmc.QMCEngine):
    """nuld's own scrambled sequences as an extensible engine: random(n)
    continues the sequence (the points num_generated .. num_generated+n of
    one scrambling, fixed by the seed)."""

    kind = None
    name = None

    @_checked()
    def __init__(self, d=2, *, scramble=True, seed=None):
        _check_d(d, self.name)
        self._seed = _seed_int(seed, self.name)  # before scipy's own check: nuld's message
        scramble = _nuld._flag(scramble, self.name, "scramble")
        qmc.QMCEngine.__init__(self, d=2, seed=seed)
        self._scramble = "owen" if scramble else "none"

    def _random(self, n=1, *, workers=1):
        if n == 0:  # as scipy's engines: an empty (0, d) array
            return np.zeros((0, 2))
        start = self.num_generated
        points = _nuld.sequence(start + n, kind=self.kind, scramble=self._scramble,
                                seed=self._seed)
        return np.asarray(points, dtype=float)[start:start + n]

    def _random_base2(self, m):
        """2^m points; for Sobol, as scipy's, only where the points drawn
        then total a power of 2 (their balance)."""
        n = 2**m
        total = self.num_generated + n
        if self.kind == "sobol" and total & (total - 1):
            raise ValueError("%s.random_base2: m: random_base2(%d) after %d points would total "
                             "%d, not a power of 2; use random(%d) to draw them anyway"
                             % (self.name, m, self.num_generated, total, n))
        return self._draw(n, "random_base2", "m")

    def _reset(self):
        qmc.QMCEngine.__init__(self, d=2, seed=self.rng_seed)
        return self

    def _fast_forward(self, n):
        self.num_generated += n
        return self


class Sobol(_SequenceEngine):
    """nuld's Owen-scrambled Sobol' points in 2D (the renderer's `sobol`),
    as scipy's qmc.Sobol(d=2, scramble=..., seed=...)."""

    kind = "sobol"
    name = "nuld.qmc.Sobol"

    @_checked("random")
    def random(self, n=1, *, workers=1):
        # The same advice scipy's Sobol gives: its balance needs 2^m points.
        n = _nuld._count(n, self.name + ".random", "n", 0)
        if n & (n - 1):
            import warnings
            warnings.warn("nuld.qmc.Sobol: the balance properties of Sobol' points need n to be "
                          "a power of 2", UserWarning, stacklevel=3)
        return self._draw(n, "random", "n")


class Halton(_SequenceEngine):
    """nuld's Owen-scrambled Halton points in 2D (bases 2 and 3), as
    scipy's qmc.Halton(d=2, scramble=..., seed=...)."""

    kind = "halton"
    name = "nuld.qmc.Halton"


class PMJ02(_SequenceEngine):
    """nuld's progressive multi-jittered (0,2) sequence in 2D (the
    renderer's `pmj02`: Christensen, Kensler and Kilpatrick 2018, made by
    Pharr's 2019 method), Owen-scrambled: every power-of-two prefix is a
    (0,2)-net. At most 65536 points."""

    kind = "pmj02"
    name = "nuld.qmc.PMJ02"


class NeuralEngine(PointSetEngine):
    """K sets a trained model (nuld train) generates from offsets drawn with
    `seed` (None, an int or a numpy Generator), at `gamma` for a model of a
    target family. Built as scipy's engines are, with its model:
    NeuralEngine(d=2, model=PATH, seed=...); the older form
    NeuralEngine(PATH, instances) works too. A model is needed: nuld ships
    one (models/disney.nuldnet), for a family whose members gamma names."""

    name = "nuld.qmc.NeuralEngine"

    @_checked()
    def __init__(self, d=2, instances=1, *, model=None, seed=None, gamma=(), n=None):
        if isinstance(d, str):  # NeuralEngine(MODEL, ...)
            if model is not None:
                raise TypeError("%s: model: given twice (first and as model=)" % self.name)
            model, d = d, 2
        _check_d(d, self.name)
        if model is None:
            raise TypeError("%s: model: expected the path of a model nuld train made, e.g. "
                            "NeuralEngine(d=2, model='m.nuldnet', seed=1) (got None)" % self.name)
        instances = _nuld._count(instances, self.name, "instances", 1)
        if n is not None:
            n = _nuld._count(n, self.name, "n", 1)
        with _as(self.name):
            points, self.target_spec = _nuld.generate_neural(
                model, instances, _seed_int(seed, self.name), gamma, n)
        PointSetEngine.__init__(self, points, seed=seed)
