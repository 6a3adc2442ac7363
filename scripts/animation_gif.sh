#!/usr/bin/env bash
# An animated fit map of a moving body: resolves every frame of a garment animation on an animated
# body (`tryon animate resolve`), renders every STEP-th frame from the front and the side with the
# garment coloured by edge strain against that frame's input garment (`tryon render --reference`,
# the resolver's fit map), and joins them into a GIF with ImageMagick's `convert`.
# With --worn, a pattern worn through the motion instead (`tryon animate drape`), coloured by edge
# strain against the garment as draped on the first frame.
# Usage: scripts/animation_gif.sh BODY.obj BODY.pc2 GARMENT.obj GARMENT.pc2 OUT.gif [STEP]
#        scripts/animation_gif.sh --worn BODY.obj BODY.pc2 PATTERN OUT.gif [STEP]
#   e.g. ../shared/data/animation/{body_hm08.obj,body_hm08_walk.pc2,
#        tshirt_female_casualsuit01_top.obj,tshirt_female_casualsuit01_top_walk.pc2}
#   or   --worn ../shared/data/animation/{body_hm08.obj,body_hm08_walk.pc2} config/patterns/hm08/dress.yaml
# Needs a build (scripts/build.sh) and the Debian package imagemagick.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
usage() {
  echo "usage: scripts/animation_gif.sh BODY.obj BODY.pc2 GARMENT.obj GARMENT.pc2 OUT.gif [STEP]" >&2
  echo "       scripts/animation_gif.sh --worn BODY.obj BODY.pc2 PATTERN OUT.gif [STEP]" >&2
  exit 2
}
WORN=0
if [[ ${1:-} == --worn ]]; then
  WORN=1
  shift
  (($# >= 4)) || usage
  BODY=$1 BODY_PC2=$2 PATTERN=$3 OUT=$4 STEP=${5:-2}
else
  (($# >= 5)) || usage
  BODY=$1 BODY_PC2=$2 GARMENT=$3 GARMENT_PC2=$4 OUT=$5 STEP=${6:-2}
fi
command -v convert >/dev/null || { echo "animation_gif: needs ImageMagick's convert (apt-get install imagemagick)" >&2; exit 2; }
TRYON=${VT_WS:-.ws}/devel/lib/virtual_tryon/tryon
[[ -x $TRYON ]] || { echo "animation_gif: no $TRYON; run scripts/build.sh first" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

if ((WORN)); then
  # The worn garment: OUT.obj (frame 0, the reference of every frame) and OUT.pc2. Exit 3 (a frame
  # not converged) still writes every frame.
  "$TRYON" animate drape --body "$BODY" --body-cache "$BODY_PC2" --pattern "$PATTERN" \
    --out "$WORK/resolved.pc2" > "$WORK/frames.jsonl" || [[ $? == 3 ]]
  GARMENT=$WORK/resolved.obj GARMENT_PC2=-
  TITLE="strain against frame 0"
else
  "$TRYON" animate resolve --body "$BODY" --body-cache "$BODY_PC2" --garment "$GARMENT" --garment-cache "$GARMENT_PC2" \
    --out "$WORK/resolved.pc2" > "$WORK/frames.jsonl" || [[ $? == 3 ]]
  TITLE="strain against the frame's input"
fi
# One OBJ per rendered frame: the body, the garment as it came, the garment resolved.
/usr/bin/python3 - "$BODY" "$BODY_PC2" "$GARMENT" "$GARMENT_PC2" "$WORK/resolved.pc2" "$WORK" "$STEP" <<'PY'
import struct, sys
import numpy as np
body, body_pc2, garment, garment_pc2, resolved_pc2, work, step = sys.argv[1:8]
def faces(path):
    return [l for l in open(path) if l.startswith("f ")]
def cache(path):
    with open(path, "rb") as f:
        head = f.read(32)
        points, samples = struct.unpack("<i", head[16:20])[0], struct.unpack("<i", head[28:32])[0]
        return np.frombuffer(f.read(), dtype="<f4").reshape(samples, points, 3)
def write(path, V, F):
    with open(path, "w") as f:
        f.writelines("v %.6f %.6f %.6f\n" % tuple(v) for v in V)
        f.writelines(F)
B, R = cache(body_pc2), cache(resolved_pc2)
# "-": no garment cache; the garment OBJ (the worn garment on frame 0) is every frame's input.
G = cache(garment_pc2) if garment_pc2 != "-" else None
rest = np.array([[float(t) for t in l.split()[1:4]] for l in open(garment) if l.startswith("v ")])
BF, GF = faces(body), faces(garment)
for i in range(0, min(len(B), len(R)), int(step)):
    write("%s/body_%03d.obj" % (work, i), B[i], BF)
    write("%s/input_%03d.obj" % (work, i), G[i] if G is not None else rest, GF)
    write("%s/fitted_%03d.obj" % (work, i), R[i], GF)
PY
frames=()
for b in "$WORK"/body_*.obj; do
  i=${b##*_}; i=${i%.obj}
  "$TRYON" render --body "$b" --garment "$WORK/fitted_$i.obj" --reference "$WORK/input_$i.obj" \
    --out "$WORK/f_$i" --title "frame $((10#$i)): $TITLE" > /dev/null 2>&1
  convert "$WORK/f_${i}_front.png" "$WORK/f_${i}_side.png" +repage +append -resize 40% +repage "$WORK/m_$i.png"
  frames+=("$WORK/m_$i.png")
done
# 30 Hz animation, every STEP-th frame: STEP / 30 s a picture (GIF delays are in 1/100 s).
convert -delay $((100 * STEP / 30)) -loop 0 "${frames[@]}" -layers Optimize "$OUT"
echo "animation_gif: wrote $OUT (${#frames[@]} pictures)"
