#!/bin/sh
# Runs issue 10's benchmark programs through LinuxCNC's planner (headless) and compares with ncplc.
# Usage: motion/compare/linuxcnc/run.sh [WORKDIR [FILTER]]   (needs linuxcnc-uspace; run from the
# repository). Issue 10's six programs and issue 22's CAM set; FILTER keeps the names containing it.
set -e
here=$(cd "$(dirname "$0")" && pwd)
work=${1:-/tmp/ncplc-linuxcnc}
mkdir -p "$work" && chmod 777 "$work"
cp "$here/mill.ini" "$here/sample.hal" "$here/drive.py" "$work/"
: > "$work/sim_mm.tbl"; echo "5220 0" > "$work/sim_mm.var"
cargo run -q --release -p motion --example linuxcnc_programs -- "$work" "${2:-}" > "$work/ncplc.txt"
for n in $(cut -d' ' -f1 "$work/ncplc.txt"); do
    # rtapi_app refuses to run as root without a fallback uid.
    (cd "$work" && RTAPI_UID=${RTAPI_UID:-65534} RTAPI_FIFO_PATH="$work/.rtapi_fifo" \
        LCNC_PROG="$work/$n.ngc" LCNC_OUT="$work/$n.txt" linuxcnc mill.ini > "$work/$n.log" 2>&1)
done
python3 "$here/analyze.py" "$work"
