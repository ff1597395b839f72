"""A notebook-style tour of nuld from Python (tools/python/README.md).

Run from the checkout after tools/build.sh:
    PYTHONPATH=build/python /usr/bin/python3 tools/python/examples/tour.py
"""
import numpy as np
from scipy.stats import qmc

import nuld
from nuld.qmc import OptimizedEngine

# A target from the CLI's SPEC strings: a Gaussian truncated to the square.
target = nuld.Target("gaussian:0.3,0.6,0.15")
print(target, "mass of [0,0.5)^2:", round(target.mass((0, 0), (0.5, 0.5)), 4))

# Owen-scrambled Sobol through the target's inverse CDF, 16 instances of 64.
sobol = nuld.sequence(64, "sobol", "owen", seed=1, instances=16, target=target)

# Sets optimized for the target (Algorithm 1's soft boxes, shortened to 300
# of the preset's 1000 epochs).
optimized = nuld.optimize(target, 64, instances=16, epochs=300, seed=1, progress=True)
for name, sets in (("sobol", sobol), ("optimized", optimized)):
    print("%-10s l2asd %.5f  dstar %.5f" % (name, nuld.discrepancy(sets, "l2asd", target).mean(),
                                            nuld.discrepancy(sets, "dstar", target).mean()))

# Uniform optimized sets as a scipy.stats.qmc engine: scipy's functions apply.
engine = OptimizedEngine("uniform", n=64, instances=4, objective="l2asd", epochs=300, seed=2)
first = engine.random(64)
print("scipy L2-star of an optimized set: %.3g (Sobol: %.3g)"
      % (qmc.discrepancy(first, method="L2-star"),
         qmc.discrepancy(qmc.Sobol(2, seed=2).random(64), method="L2-star")))

# Render the built-in scene with two backends and compare with a reference.
reference = nuld.render("default", backend="halton", spp=256, resolution=(96, 64))
for backend in ("independent", "sobol"):
    image = nuld.render("default", backend=backend, spp=16, resolution=(96, 64), seed=3)
    print("%-12s 16 spp: MSE %.3g" % (backend, nuld.compare(image, reference)["mse"]))
print("image", image.shape, image.dtype, "mean %.4f" % float(np.mean(image)))
