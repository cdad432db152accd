#!/usr/bin/env bash
# ctest driver of `chatter-mpi lobes --samples N` (docs/scaling.md). Usage:
#   mpi_lobes.sh MODE MPIEXEC CHATTER CHATTER_MPI NP CONFIG SPREADS [lobes options...]
# The config used is CONFIG with an [uncertainty] table of SPREADS appended
# (TOML lines separated by "|"; "none": no table), written to a scratch dir.
# MODE:
#   compare  `chatter lobes` and `mpirun -n NP chatter-mpi lobes` with the same
#            options (plus --table t.csv --json t.json --probability-table
#            p.csv --plot l.png), each in its own directory: every file and the
#            standard output must be the same bytes.
#   exit     CHATTER_MPI_FAIL_AFTER_ITEMS=1 (rank 1 dies after one block):
#            non-zero exit, stderr names rank 1, no output file (nor .partial).
#   throw    CHATTER_MPI_THROW_AFTER_ITEMS=1 (rank 1 throws): non-zero exit,
#            one "chatter-mpi: rank 1: ..." message, no output file.
#   bad      the --samples request or the config is bad input: exit 2 as
#            `chatter`, exactly one "chatter-mpi:" line (rank 0's) with
#            chatter's text, which names --samples; no output file.
#   refuse   without --samples: exit 2, one message asking for --samples.
set -u
mode=$1 mpiexec=$2 chatter=$3 chatter_mpi=$4 np=$5 config=$6 spreads=$7
shift 7
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cfg=$work/u.toml
cp "$config" "$cfg"
[ "$spreads" = none ] || printf '\n[uncertainty]\n%s\n' "$(echo "$spreads" | tr "|" "\n")" >> "$cfg"
run_mpi() { "$mpiexec" -n "$np" --oversubscribe "$chatter_mpi" lobes "$cfg" "$@"; }
outputs=(--table t.csv --json t.json --probability-table p.csv --plot l.png)
no_outputs() { ls "$work"/t.csv* "$work"/t.json* "$work"/p.csv* "$work"/l.* > /dev/null 2>&1 && fail "an output was left: $(ls "$work")"; }

case $mode in
  compare)
    mkdir "$work/one" "$work/mpi"
    (cd "$work/one" && "$chatter" lobes "$cfg" "$@" "${outputs[@]}" > stdout.txt) || fail "chatter lobes failed"
    (cd "$work/mpi" && run_mpi "$@" "${outputs[@]}" > stdout.txt) || fail "chatter-mpi lobes failed"
    for f in t.csv t.json p.csv l.png l.gp l.dat stdout.txt; do
      [ -s "$work/one/$f" ] || fail "chatter wrote no $f"
      cmp "$work/one/$f" "$work/mpi/$f" || fail "$f differs between chatter and chatter-mpi -n $np"
    done
    head -1 "$work/one/t.csv" | grep -q depth_limit_p05_mm || fail "no quantile columns in the table"
    echo "same bytes: t.csv ($(wc -l < "$work/one/t.csv") lines), t.json, p.csv, l.png, l.gp, l.dat, stdout"
    ;;
  exit | throw)
    var=CHATTER_MPI_FAIL_AFTER_ITEMS
    [ "$mode" = throw ] && var=CHATTER_MPI_THROW_AFTER_ITEMS
    (cd "$work" && env "$var=1" "$mpiexec" -n "$np" --oversubscribe "$chatter_mpi" lobes "$cfg" "$@" \
       "${outputs[@]}" > out.txt 2> err.txt)
    rc=$?
    cat "$work/err.txt" >&2
    [ "$rc" -ne 0 ] || fail "exit status 0 after a rank failed"
    grep -q "chatter-mpi: rank 1: $var=1" "$work/err.txt" || fail "no message naming rank 1"
    if [ "$mode" = exit ]; then
      grep -q "Exit code: *3" "$work/err.txt" || fail "mpirun did not report the rank's exit status 3"
    else
      grep -q "(the run failed: nothing written)" "$work/err.txt" || fail "rank 0 did not report the failure"
      [ "$(grep -c '^chatter-mpi:' "$work/err.txt")" -eq 1 ] || fail "not exactly one chatter-mpi message"
    fi
    no_outputs
    echo "failed as it must: exit $rc, no output"
    ;;
  bad)
    (cd "$work" && "$chatter" lobes "$cfg" "$@" "${outputs[@]}" 2> one.txt)
    rc_one=$?
    (cd "$work" && run_mpi "$@" "${outputs[@]}" > out.txt 2> err.txt)
    rc=$?
    cat "$work/err.txt" >&2
    [ "$rc" -eq 2 ] || fail "exit status $rc, expected 2"
    [ "$rc_one" -eq 2 ] || fail "chatter lobes exit status $rc_one, expected 2"
    [ "$(grep -c '^chatter-mpi:' "$work/err.txt")" -eq 1 ] || fail "not exactly one chatter-mpi message"
    [ "$(sed -n 's/^chatter-mpi: //p' "$work/err.txt")" = "$(sed -n 's/^chatter: //p' "$work/one.txt")" ] ||
      fail "message differs from chatter's: $(cat "$work/one.txt")"
    grep -q '^chatter-mpi: --samples' "$work/err.txt" || fail "the message does not name --samples"
    no_outputs
    echo "bad input: exit 2, one message: $(sed -n 's/^chatter: //p' "$work/one.txt")"
    ;;
  refuse)
    (cd "$work" && run_mpi "$@" --table t.csv > out.txt 2> err.txt)
    rc=$?
    cat "$work/err.txt" >&2
    [ "$rc" -eq 2 ] || fail "exit status $rc, expected 2"
    [ "$(grep -c '^chatter-mpi:' "$work/err.txt")" -eq 1 ] || fail "not exactly one chatter-mpi message"
    grep -q "give --samples N" "$work/err.txt" || fail "the message does not ask for --samples"
    no_outputs
    echo "without --samples: refused, exit 2"
    ;;
  *) fail "unknown mode $mode" ;;
esac
