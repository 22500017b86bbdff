#!/usr/bin/env bash
# Soak test: one long `glmbslam run` (default 20 000 frames) on the rendered KITTI sequence 00 driven forward,
# backward, forward, … (the 4541 rendered frames are linked, not copied, so the long sequence costs no extra
# disk; the poses follow the same order, so the ground truth stays exact). While it runs, the frames done (the
# streamed trajectory's lines) and the memory of the process (VmRSS, VmHWM) are sampled every few seconds.
# Prints the peak RSS at 1k, 5k and the last frame count, the time per frame of each block of 1000 frames, and
# the two checks of issue-level targets: peak RSS at the end within 10 % of that at 5k frames, and no slowdown
# (time per frame of the last blocks vs the first ones after warm-up).
#
# Usage: scripts/soak.sh [FRAMES] [WORK_DIR]       (defaults 20000, /tmp/glmbslam_soak)
# Environment: GLMBSLAM (executable; default build/src/app/glmbslam), GLMBSLAM_DATA (data root; default
#              ../shared/data), SOAK_ARGS (extra `run` arguments, e.g. "--particles 10"), SAMPLE_S (default 5)
# The run is niced and single-threaded (--threads 1); the rendering uses every core.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
frames="${1:-20000}"
work="${2:-/tmp/glmbslam_soak}"
bin="${GLMBSLAM:-$root/build/src/app/glmbslam}"
data="${GLMBSLAM_DATA:-$root/../shared/data}"
sample_s="${SAMPLE_S:-5}"
[ -x "$bin" ] || { echo "soak: $bin not found (build it or set GLMBSLAM)" >&2; exit 2; }
gt="$data/kitti_odometry/poses/00.txt"
[ -f "$gt" ] || { echo "soak: $gt not found (set GLMBSLAM_DATA)" >&2; exit 2; }
mkdir -p "$work"

# 1. Render sequence 00 once (kept between soak runs).
render="$work/render"
if [ ! -f "$render/poses/00.txt" ]; then
  echo "soak: rendering sequence 00 into $render"
  "$bin" --log-level warn render --out "$render" --poses "$gt" --calib kitti00-02
fi
src="$render/sequences/00"
n_src=$(wc -l <"$render/poses/00.txt")

# 2. The long sequence: frame i shows source frame f(i), forward 0..n-1, then backward n-2..1, then forward again.
seq="$work/long/sequences/00"
rm -rf "$work/long"
mkdir -p "$seq/image_0" "$seq/image_1" "$work/long/poses"
cp "$src/calib.txt" "$seq/calib.txt"
awk -v n="$n_src" -v frames="$frames" 'BEGIN {
  period = 2 * (n - 1)
  for (i = 0; i < frames; ++i) { p = i % period; print (p < n ? p : period - p) }
}' >"$work/long/order.txt"
i=0
while read -r f; do
  name=$(printf '%06d.png' "$i")
  srcname=$(printf '%06d.png' "$f")
  ln -s "$src/image_0/$srcname" "$seq/image_0/$name"
  ln -s "$src/image_1/$srcname" "$seq/image_1/$name"
  i=$((i + 1))
done <"$work/long/order.txt"
awk -v frames="$frames" 'BEGIN { for (i = 0; i < frames; ++i) printf "%.6e\n", i * 0.1 }' >"$seq/times.txt"
awk 'NR == FNR { pose[FNR - 1] = $0; next } { print pose[$1] }' "$render/poses/00.txt" "$work/long/order.txt" \
  >"$work/long/poses/00.txt"

# 3. The run, sampled.
out="$work/out"
rm -rf "$out"
samples="$work/samples.csv"
echo "seconds,frames,rss_mib,hwm_mib" >"$samples"
start=$(date +%s.%N)
# shellcheck disable=SC2086
nice "$bin" --threads 1 --log-level warn run "$seq" --out "$out" ${SOAK_ARGS:-} >"$work/run.log" 2>&1 &
pid=$!
while kill -0 "$pid" 2>/dev/null; do
  done_frames=$(wc -l <"$out/trajectory.streaming.txt" 2>/dev/null || echo 0)
  rss=$(awk '/^VmRSS:/ { print $2 / 1024 }' "/proc/$pid/status" 2>/dev/null || echo 0)
  hwm=$(awk '/^VmHWM:/ { print $2 / 1024 }' "/proc/$pid/status" 2>/dev/null || echo 0)
  now=$(date +%s.%N)
  if [ -n "$rss" ] && [ -n "$hwm" ]; then
    awk -v a="$now" -v b="$start" -v f="$done_frames" -v r="$rss" -v h="$hwm" \
      'BEGIN { printf "%.1f,%d,%.1f,%.1f\n", a - b, f, r, h }' >>"$samples"
  fi
  sleep "$sample_s"
done
wait "$pid" || { echo "soak: glmbslam failed, see $work/run.log" >&2; exit 1; }

# 4. Report.
awk -F, -v frames="$frames" '
  NR == 1 { next }
  { t[NR] = $1; f[NR] = $2; hwm[NR] = $4; last = NR }
  END {
    for (i = 2; i <= last; ++i) {
      if (!a1 && f[i] >= 1000) { a1 = hwm[i]; }
      if (!a5 && f[i] >= 5000) { a5 = hwm[i]; }
    }
    end_hwm = hwm[last]; end_f = f[last]
    printf "peak RSS (VmHWM): %.1f MiB at 1k frames, %.1f MiB at 5k, %.1f MiB at %d frames", a1, a5, end_hwm, end_f
    if (a5 > 0) printf " (%+.1f %% vs 5k)", 100 * (end_hwm - a5) / a5
    printf "\n"
    # time per frame per block of 1000 frames (first sample at or after each boundary)
    b = 0; prev_t = 0; prev_f = 0
    for (i = 2; i <= last; ++i) {
      if (f[i] >= (b + 1) * 1000) {
        ms[b] = 1000 * (t[i] - prev_t) / (f[i] - prev_f); prev_t = t[i]; prev_f = f[i]; ++b
      }
    }
    printf "ms per frame per 1000-frame block:"
    for (k = 0; k < b; ++k) printf " %.1f", ms[k]
    printf "\n"
    if (b >= 4) {
      first = (ms[1] + ms[2]) / 2; final = (ms[b - 2] + ms[b - 1]) / 2
      printf "blocks 2-3 %.1f ms/frame, last two %.1f ms/frame (%+.1f %%)\n", first, final, 100 * (final - first) / first
    }
  }' "$samples"
grep -E '"(frames|fps|peak_rss_mib|wall_s)"' "$out/metrics.json" || true
echo "soak: samples in $samples, outputs in $out"
