#!/usr/bin/env bash
# ctest driver of chatter-mpi (docs/scaling.md). Usage:
#   mpi_surface.sh MODE MPIEXEC CHATTER CHATTER_MPI NP CONFIG [surface options...]
# MODE:
#   compare  `chatter surface` and `mpirun -n NP chatter-mpi surface` with the
#            same options (plus --table t.csv --plot s.png), each in its own
#            directory: the table, the plot's script, data and image and the
#            standard output must be the same bytes.
#   exit     with CHATTER_MPI_FAIL_AFTER_ITEMS=1 (rank 1 dies after one item):
#            non-zero exit, stderr names rank 1, no table (nor .partial).
#   throw    with CHATTER_MPI_THROW_AFTER_ITEMS=1 (rank 1 throws): non-zero
#            exit, one "chatter-mpi: rank 1: ..." message, no table.
#   bad      the options are bad input: exit 2, exactly one "chatter-mpi:"
#            line (rank 0's, not NP copies), the same text as `chatter`'s, no table.
set -u
mode=$1 mpiexec=$2 chatter=$3 chatter_mpi=$4 np=$5 config=$6
shift 6
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run_mpi() { "$mpiexec" -n "$np" --oversubscribe "$chatter_mpi" surface "$config" "$@"; }

case $mode in
  compare)
    mkdir "$work/one" "$work/mpi"
    (cd "$work/one" && "$chatter" surface "$config" "$@" --table t.csv --plot s.png > stdout.txt) ||
      fail "chatter surface failed"
    (cd "$work/mpi" && run_mpi "$@" --table t.csv --plot s.png > stdout.txt) || fail "chatter-mpi surface failed"
    for f in t.csv s.png s.gp s.dat stdout.txt; do
      [ -s "$work/one/$f" ] || fail "chatter wrote no $f"
      cmp "$work/one/$f" "$work/mpi/$f" || fail "$f differs between chatter and chatter-mpi -n $np"
    done
    echo "same bytes: t.csv ($(wc -l < "$work/one/t.csv") lines), s.png, s.gp, s.dat, stdout"
    ;;
  exit | throw)
    var=CHATTER_MPI_FAIL_AFTER_ITEMS
    [ "$mode" = throw ] && var=CHATTER_MPI_THROW_AFTER_ITEMS
    (cd "$work" && env "$var=1" "$mpiexec" -n "$np" --oversubscribe "$chatter_mpi" surface "$config" "$@" \
       --table t.csv > out.txt 2> err.txt)
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
    ls "$work"/t.csv* > /dev/null 2>&1 && fail "a table (or its .partial) was left: $(ls "$work")"
    echo "failed as it must: exit $rc, no table"
    ;;
  bad)
    (cd "$work" && "$chatter" surface "$config" "$@" --table t.csv 2> one.txt)
    rc_one=$?
    (cd "$work" && run_mpi "$@" --table t.csv > out.txt 2> err.txt)
    rc=$?
    cat "$work/err.txt" >&2
    [ "$rc" -eq 2 ] || fail "exit status $rc, expected 2"
    [ "$rc_one" -eq 2 ] || fail "chatter surface exit status $rc_one, expected 2"
    [ "$(grep -c '^chatter-mpi:' "$work/err.txt")" -eq 1 ] || fail "not exactly one chatter-mpi message"
    [ "$(sed -n 's/^chatter-mpi: //p' "$work/err.txt")" = "$(sed -n 's/^chatter: //p' "$work/one.txt")" ] ||
      fail "message differs from chatter's: $(cat "$work/one.txt")"
    ls "$work"/t.csv* > /dev/null 2>&1 && fail "a table was written"
    echo "bad input: exit 2, one message"
    ;;
  *) fail "unknown mode $mode" ;;
esac
