# Whether an estimate agrees with the simulator's truth: each parameter hrg-bench or hrg-estimate
# prints as "  delta2  +3.0000000000e-01 ± 3.8e-09  ..." must be within 5 of its reported standard
# deviations of the truth. Usage (busybox awk in the QEMU guest):
#   awk -v truth="D1 D2 D3 D4 D5 D6" -f estimate_within_5_std.awk ESTIMATE_OUTPUT
# ξ's truth is 0 (the kernel tests' simulators have none). Exit 1 unless all six δ agree and nothing
# printed is off.
BEGIN { split(truth, d, " ");
        for (i = 1; i <= 6; ++i) want["delta" i] = d[i];
        for (i = 1; i <= 4; ++i) want["xi" i] = 0; }
($1 in want) && $3 == "\302\261" && !($1 in seen) {
  seen[$1] = 1; err = $2 - want[$1]; if (err < 0) err = -err;
  ok = ($4 > 0 && err <= 5 * $4);
  printf "%s: %s %s %s truth %s (%s)\n", $1, $2, $3, $4, want[$1], ok ? "within 5 std" : "OFF";
  if (ok) ++good; else ++bad; }
END { if (good < 6 || bad > 0) { print "estimate: " good " agree, " bad " off"; exit 1 } }
