#!/usr/bin/env bash
# Compile CPU per command and per library, the numbers DEVELOPERS.md's CI section quotes.
#
# As a compiler launcher (no ccache: every command really compiles), in a scratch build folder:
#   LEVER_CPU_LOG=$PWD/cpu.log cmake -S . -B build-cpu -DCMAKE_BUILD_TYPE=Release \
#     -DCMAKE_CXX_COMPILER_LAUNCHER=$PWD/scripts/compile_cpu.sh
#   LEVER_CPU_LOG=$PWD/cpu.log cmake --build build-cpu --target lever_check
# each compile appends "user-seconds system-seconds object" to $LEVER_CPU_LOG. Then
#   scripts/compile_cpu.sh --sum cpu.log
# prints user + system seconds per target (the folder its objects are in). CPU time, not wall
# time: it is what two cores share, and it varies less with the machine's load.
set -u
if [ "${1:-}" = "--sum" ]; then
  awk '{ target = $3; sub(/\.dir\/.*/, "", target); sub(/.*\//, "", target)
         cpu[target] += $1 + $2; objects[target]++ }
       END { for (t in cpu) printf "%-24s %3d objects %8.1f s\n", t, objects[t], cpu[t] }' "$2" | sort
  exit 0
fi
out=unknown
prev=
for arg in "$@"; do
  [ "$prev" = "-o" ] && out=$arg
  prev=$arg
done
log=${LEVER_CPU_LOG:?set LEVER_CPU_LOG to the log file}
# bash's own `time` (no package needed): its report goes to the log, the compiler's messages to
# stderr as usual; the compiler's exit status is the script's
TIMEFORMAT="%U %S $out"
{ time "$@" 2>&3; } 3>&2 2>>"$log"
