#!/bin/sh
# SPDX-License-Identifier: MIT
# Messages that say what is wrong, end to end: each bad input exits 2 (a failed
# optimisation 1) with a message naming the file and line, the vertex ids or the reason
# from the system, and no byte that a terminal would not show.
# Usage: messages.sh TOOL DATA WORK
t=$1
d=$2
o=$3
rm -rf "$o" && mkdir -p "$o" && cd "$o" || exit 1
failures=0
# check EXIT REGEX COMMAND...: COMMAND exits EXIT and its output, lines joined by spaces,
# matches REGEX (grep -E).
check() {
  want_rc=$1
  want=$2
  shift 2
  out=$("$@" 2>&1)
  rc=$?
  printf '$ %s\n%s\n' "$*" "$out" | LC_ALL=C tr -c '[:print:]\n' '?'
  if [ "$rc" -ne "$want_rc" ] || ! printf '%s' "$out" | tr '\n' ' ' | grep -Eq -- "$want"; then
    echo "FAILED (exit $rc, expected $want_rc and /$want/)"
    failures=$((failures + 1))
  fi
  if printf '%s' "$out" | LC_ALL=C grep -q '[^[:print:][:space:]]'; then
    echo "FAILED: raw bytes in the message"
    failures=$((failures + 1))
  fi
}
edge='EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1'

# A vertex of the wrong type: named by its tag, not by a C++ type name.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 1 0\n%s\n' "$edge" > wrong_type.g2o
check 2 "wrong_type.g2o:3: EDGE_SE2: vertex 1 has the wrong type for slot 1: it is a VERTEX_XY, the slot takes VERTEX_SE2" \
  "$t" optimize wrong_type.g2o

# Files that do not open: the system's reason, no ':0'.
check 2 '/nonexistent/a.tum: cannot open: No such file or directory' "$t" eval ape /nonexistent/a.tum /nonexistent/b.tum
check 2 '/nonexistent/m.txt: cannot open: No such file or directory' "$t" convert /nonexistent/m.txt m.g2o
check 2 '/nonexistent/h.npz: cannot open: No such file or directory' "$t" info /nonexistent/h.npz

# Ids and numbers out of range are called so.
printf 'VERTEX_SE2 2147483648 0 0 0\n' > id_int.g2o
check 2 "id_int.g2o:1: VERTEX_SE2: value 1 '2147483648' is out of the range of vertex ids" "$t" info id_int.g2o
printf 'VERTEX_SE2 999999999999 0 0 0\n' > id_long.g2o
check 2 "id_long.g2o:1: VERTEX_SE2: value 1 '999999999999' is out of the range of vertex ids" "$t" info id_long.g2o
printf 'VERTEX_SE2 0 1e400 0 0\n' > big.g2o
check 2 "big.g2o:1: VERTEX_SE2: value 2 '1e400' is out of the range of a double" "$t" info big.g2o
printf '0 0 0 0 0 0 0 1\n1e400 0 0 0 0 0 0 1\n' > big.tum
check 2 "big.tum:2: token 1 '1e400' is out of the range of a double" "$t" eval ape big.tum big.tum
mkdir -p scenario
printf '0 0 1e400\n' > scenario/x0.txt
printf '10 0\n' > scenario/wp.txt
printf '5 5\n' > scenario/lm.txt
check 2 "scenario/x0.txt:1: '1e400' is out of the range of a double" "$t" drivebot --scenario "$o/scenario" --out drivebot_out

# Invisible and binary bytes escaped; byte-order marks named.
printf '\357\273\277VERTEX_SE2 0 0 0 0\n' > bom.g2o
check 2 "bom.g2o:1: unknown tag '.xEF.xBB.xBFVERTEX_SE2' .a UTF-8 byte-order mark" "$t" info bom.g2o
printf '\377\376V\000E\000R\000T\000E\000X\000\n\000' > utf16.g2o
check 2 "utf16.g2o:1: unknown tag '.xFF.xFEV.x00E.x00R.x00T.x00E.x00X.x00' .a UTF-16 byte-order mark" "$t" info utf16.g2o
printf '\177ELF\002\001\001\000\000\000\033[31m\n' > binary.g2o
check 2 "binary.g2o:1: unknown tag '.x7FELF.x02.x01.x01.x00.x00.x00.x1B.31m'" "$t" info binary.g2o
printf '\357\273\2770 0 0 0 0 0 0 1\n' > bom.tum
check 2 "bom.tum:1: token 1 '.xEF.xBB.xBF0' .a UTF-8 byte-order mark" "$t" eval ape bom.tum bom.tum
printf '0 0 0 0 0 0 0 1\n1 \033[2J 0 0 0 0 0 1\n' > escape.tum
check 2 "escape.tum:2: token 2 '.x1B.2J' is not a number" "$t" eval ape escape.tum escape.tum

# An initial chi2 that is not finite names its edge (line, vertex ids) and the overflow.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nFIX 0\nEDGE_SE2 0 1 10 0 0 1e308 0 0 1e308 0 1e308\n' > overflow.g2o
check 1 "initial chi2 is not finite: the edge joining vertices 0, 1: its error is finite .largest entry 10. but e.T Omega e overflows the range of a double .information entries up to 1e.308.*that edge is on line 4 of overflow.g2o" \
  "$t" optimize overflow.g2o --init none -o overflow_out.g2o
printf 'VERTEX_SE2 0 1e308 0 0\nVERTEX_SE2 1 -1e308 0 0\nFIX 0\n%s\n' "$edge" > inf_error.g2o
check 1 "the edge joining vertices 0, 1: its error is not finite at the initial estimate.*that edge is on line 4" \
  "$t" optimize inf_error.g2o --init none
[ ! -e overflow_out.g2o ] || { echo "FAILED: overflow_out.g2o written"; failures=$((failures + 1)); }
# An information matrix beyond double precision is named as the reason, not the edge count.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nFIX 0\nEDGE_SE2 0 1 1 0 0 1e308 0 0 1 0 1\n' > spread.g2o
check 2 "vertex 1 .VERTEX_SE2.: its one edge .from vertex 0. determines only 1 of its 3 directions: the information matrix of one of its edges has eigenvalues 1e.308 times apart.*line 4" \
  "$t" optimize spread.g2o --init none

# TUM files out of time order.
printf '1 0 0 0 0 0 0 1\n0.5 1 0 0 0 0 0 1\n' > decreasing.tum
check 2 "decreasing.tum:2: timestamp 0.5 is not after the previous pose's .1." "$t" eval ape decreasing.tum decreasing.tum
printf '1 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n' > repeated.tum
check 2 "repeated.tum:2: timestamp 1 is not after the previous pose's .1." "$t" eval ape repeated.tum repeated.tum

# Lines longer than the readers' bound (1 MiB) are refused with their line.
{ printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 '; head -c 1100000 /dev/zero | tr '\0' 1; printf '\n'; } > long.g2o
check 2 "long.g2o:2: the line is longer than 1048576 bytes" "$t" info long.g2o
{ printf '0 0 0 0 0 0 0 1\n'; head -c 1100000 /dev/zero | tr '\0' 1; } > long.tum
check 2 "long.tum:2: the line is longer than 1048576 bytes" "$t" eval ape long.tum long.tum

# A measurement whose term overflows is named before the default initialisation, which
# would spread it to every vertex (and an observability report would blame them all).
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n%s\nEDGE_SE2 1 2 1e300 0 0 1 0 0 1 0 1\n' "$edge" > huge.g2o
check 1 "initial chi2 is not finite: the edge joining vertices 1, 2: its error is finite .largest entry 1e.300. but e.T Omega e overflows.*that edge is on line 5 of huge.g2o.*not writing huge_out.g2o" \
  "$t" optimize huge.g2o -o huge_out.g2o
# --drop-unobservable that would leave nothing to optimise writes no empty result.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 1 0\nEDGE_BEARING_SE2_XY 0 1 0 1\n' > nothing_left.g2o
check 2 "nothing is left to optimise after --drop-unobservable" \
  "$t" optimize nothing_left.g2o --init none --drop-unobservable -o nothing_out.g2o
[ ! -e huge_out.g2o ] && [ ! -e nothing_out.g2o ] || { echo "FAILED: output written"; failures=$((failures + 1)); }

# A folder given as the input, a file given as eval's plot folder.
check 2 "$PWD: is a folder, not a file" "$t" optimize "$PWD" -o folder_out.g2o
printf '0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n' > two.tum
check 2 "--plot: two.tum is a file, not a folder" "$t" eval ape two.tum two.tum --plot two.tum

# A trajectory given to convert is named as one, not read as a matrix.
check 2 "two.tum is named as a tum trajectory, not a graph" "$t" convert two.tum two.g2o

# One file under two spellings is one file; a second output's missing folder leaves no
# first output (simulate's --truth, add-outliers' --list).
"$t" simulate --poses 20 -o in20.g2o > /dev/null
check 2 "is named for two outputs" "$t" simulate --poses 20 -o sim.g2o --truth ./sim.g2o
check 2 "is named for two outputs" "$t" optimize in20.g2o -o out2.g2o --marginals ./out2.g2o
check 2 "nodir/t.g2o: the folder nodir does not exist" "$t" simulate --poses 20 -o sim.g2o --truth nodir/t.g2o
check 2 "nodir/l.txt: the folder nodir does not exist" "$t" add-outliers in20.g2o -o outl.g2o --count 1 --list nodir/l.txt
[ ! -e sim.g2o ] && [ ! -e out2.g2o ] && [ ! -e outl.g2o ] || { echo "FAILED: first output written: $(ls)"; failures=$((failures + 1)); }

# DriveBot's results are staged in their folder and put in place together: a failing plot
# leaves none of them; a staging folder that a killed run left is removed by the next run.
printf '#!/bin/sh\ncase "$1" in -c) exec /usr/bin/python3 "$@";; esac\necho "ValueError: boom" >&2\nexit 1\n' > failing_python
chmod +x failing_python
if /usr/bin/python3 -c 'import matplotlib' 2> /dev/null; then
  check 2 "plot script plot_drivebot.py failed .exit 1.: ValueError: boom" \
    env GRAPHSLAM_PYTHON=./failing_python "$t" drivebot --experiment q1_b --max-steps 100 --out db --plot -q
  [ -z "$(ls -A db)" ] || { echo "FAILED: db holds $(ls -A db)"; failures=$((failures + 1)); }
fi
mkdir -p db/.graphslam-999999999-staging
"$t" drivebot --experiment q1_b --max-steps 100 --out db -q > /dev/null
[ "$(ls -A db | tr '\n' ' ')" = "final.g2o graph_stats.csv landmarks.csv scenario.csv steps.csv summary.csv " ] ||
  { echo "FAILED: db holds $(ls -A db)"; failures=$((failures + 1)); }

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed"; exit 1; }
