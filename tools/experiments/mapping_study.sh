#!/usr/bin/env bash
# Result 3 of the optimizer issue (the supplement's Fig. 3): optimizing with
# density mapping, unmapped with clamping, and unmapped with toroidal
# wrapping, on the quarter-disc and image targets. Writes OUT/mapping.csv
# (final L2asd, D*, and the fraction of points where the density is zero)
# and one picture per variant. Usage: mapping_study.sh OUT [N]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
n=${2:-256}
prepare_output "$out"
csv="$out/mapping.csv"
echo "target,mapping,lr,l2asd,dstar,zero_density_fraction" >"$csv"
# Unmapped points start uniform and must travel to the target: the preset's
# learning rate (1e-4) and a ten times larger one.
for spec in quarterdisc "image:$out/test_image.pfm"; do
  name=${spec%%:*}
  for lr in 1e-4 1e-3; do
    for mapping in mapped clamp toroidal; do
      f="$out/${name}_${mapping}_$lr.ptsb"
      "$nuld" optimize --target "$spec" --n "$n" --instances 8 --seed 1 --mapping "$mapping" \
        --lr "$lr" -q -o "$f" >/dev/null
      "$nuld" plot "$f" -o "$out/${name}_${mapping}_$lr.png" --size 384 2>/dev/null
      zero=$("$nuld" eval "$f" --target "$spec" --zero-density | awk '{print $2}')
      echo "$name,$mapping,$lr,$(l2_dstar "$f" "$spec"),$zero" >>"$csv"
    done
  done
done
column -s, -t "$csv"
# One figure: the three variants side by side for each target and learning rate.
"$python" - "$out" <<'PY'
import os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.image as mpimg
import matplotlib.pyplot as plt
out = sys.argv[1]
rows = [(t, lr) for t in ("quarterdisc", "image") for lr in ("1e-4", "1e-3")]
fig, axes = plt.subplots(len(rows), 3, figsize=(9, 3 * len(rows)))
for r, (t, lr) in enumerate(rows):
    for c, m in enumerate(("mapped", "clamp", "toroidal")):
        ax = axes[r][c]
        ax.imshow(mpimg.imread(f"{out}/{t}_{m}_{lr}.png"))
        ax.set_title(f"{t}, {m}, lr {lr}", fontsize=9)
        ax.axis("off")
fig.tight_layout()
fig.savefig(f"{out}/mapping.tmp.png", dpi=90)
os.replace(f"{out}/mapping.tmp.png", f"{out}/mapping.png")
PY
