#!/usr/bin/env bash
# Trains the shipped Disney-family model, models/disney.nuldnet
# (models/README.md): one graph generator for every Disney material's lobe
# tables as the renderer builds them under MIS (renderer/lobe_tables.h: on
# the sphere, 64 x 32 cells, mix 1), for 16 to 64 points.
# One thread, so the run is the same on every machine; it checkpoints
# (OUTPUT.ckpt) and resumes where it stopped when run again.
#
# Usage: tools/train_disney_model.sh [OUTPUT]   (default: models/disney.nuldnet)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
nuld=${NULD:-"$root/build/nuld"}
[[ -x "$nuld" ]] || { echo "build first: tools/build.sh (or set NULD=path/to/nuld)" >&2; exit 1; }
out=${1:-"$root/models/disney.nuldnet"}
resume=--fresh
[[ -f "$out.ckpt" ]] && resume=--resume
exec "$nuld" train --arch graph --base owen --discrepancy-gradient --stages 4 \
  --target family:disney-material:res=64,mix=1 --n 16,32,64 \
  --lr 1e-3 --lr-end 1e-5 --steps 3000 --seed 2 --threads 1 "$resume" -o "$out"
