#!/usr/bin/env bash
# The real-time player on a busy machine: build/bench/playback_load_bench on a
# stream (default: the demo's out/demo/capture.fvv) with 0, 1 and 2 cores kept
# busy by stress-ng and through a load step, then the step's timeline plotted
# by gnuplot (budget, share of texture bytes decoded, fps, PSNR over the actor
# against the whole decode). docs/player.md has the figures.
# Usage: bench/run_playback_load_bench.sh [STREAM] [seconds per condition, default 20]
set -euo pipefail
cd "$(dirname "$0")/.."
stream=${1:-out/demo/capture.fvv}
seconds=${2:-20}
if [ ! -f "$stream" ]; then
  echo "run_playback_load_bench: no stream at $stream (tools/demo.sh writes out/demo/capture.fvv)" >&2
  exit 2
fi
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target playback_load_bench >/dev/null
out=${FVV_BENCH_DIR:-out/playback_load_bench}
mkdir -p "$out"
build/bench/playback_load_bench "$stream" --seconds "$seconds" --csv "$out/step.csv" |
  tee "$out/summary.txt"

# The load step's timeline: the loaded interval shaded, one panel per measure.
read -r on off < <(sed -n 's/^# load step: 2 cores busy from \([0-9.]*\) s to \([0-9.]*\) s$/\1 \2/p' \
  "$out/step.csv")
gnuplot <<GNUPLOT
set terminal pngcairo size 1100,900 font ",11"
set output "$out/step.png"
set datafile separator ","
set key top right
set multiplot layout 4,1 title "fvv play under a load step: stress-ng --cpu 2 from $on s to $off s ($stream)"
set object 1 rect from $on, graph 0 to $off, graph 1 fillcolor rgb "#f4d0d0" fillstyle solid noborder behind
set xrange [0:*]
set ylabel "budget (ms)"
plot "$out/step.csv" every ::2 using 1:4 with steps lw 2 lc rgb "#1f5fa0" title "time budget per GOP"
set ylabel "bytes decoded (%)"
set key bottom left
set yrange [0:105]
plot "$out/step.csv" every ::2 using 1:(100*\$5) with steps lw 2 lc rgb "#207020" title "share of the GOP's texture bytes"
set yrange [0:*]
set ylabel "fps"
plot "$out/step.csv" every ::2 using 1:6 with lines lw 2 lc rgb "#a05010" title "frames drawn (last 0.5 s)"
set ylabel "PSNR (dB)"
set xlabel "time (s)"
set yrange [20:*]
plot "$out/step.csv" every ::2 using 1:7 with points pt 7 ps 0.4 lc rgb "#602080" title "actor PSNR against the whole decode", 25 with lines dt 2 lc rgb "black" title "25 dB"
unset multiplot
GNUPLOT
echo "plot: $out/step.png"
