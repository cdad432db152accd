"""Long solves release the GIL; repeated calls do not grow memory."""
import os
import threading
import time

import chatter
from conftest import SOURCE_DIR

# While a solve of about a second runs with the GIL released, a Python thread
# counting in a loop makes millions of steps; with the GIL held it makes
# none until the solve returns (the call is one bytecode). 1000 steps is far
# below the first and far above the second.
MIN_STEPS_DURING_SOLVE = 1000


def test_other_thread_runs_during_a_solve():
    job = chatter.load(SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml")
    steps = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            steps[0] += 1

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.05)
    before = steps[0]
    table = chatter.lobes(job, "sdm", rpm_points=40, threads=1)
    during = steps[0] - before
    stop.set()
    t.join()
    assert len(table["spindle_rpm"]) == 40
    assert during >= MIN_STEPS_DURING_SOLVE, f"counter advanced {during} steps during the solve"


def test_two_python_threads_solve_in_parallel_with_same_numbers():
    job = chatter.load(SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml")
    results = [None, None]

    def run(i):
        results[i] = chatter.lobes(job, "sdm", rpm_points=10, threads=1)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in results[0]:
        assert results[0][k].tobytes() == results[1][k].tobytes(), k


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


# 10^5 calls: a leak of even 16 bytes per call (one small object) would add
# 1.6 MB; allocator noise after a warm-up stays well under 1 MB.
POINT_CALLS = 100_000
MAX_RSS_GROWTH_BYTES = 1_500_000


def test_no_memory_growth_over_many_point_calls():
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    for _ in range(5000):  # warm-up: solver cache, allocator pools
        chatter.point(job, rpm=1200, depth_mm=1.5)
    start = rss_bytes()
    for i in range(POINT_CALLS):
        chatter.point(job, rpm=1200 + (i % 7), depth_mm=1.5)
    growth = rss_bytes() - start
    assert growth < MAX_RSS_GROWTH_BYTES, f"RSS grew by {growth} bytes over {POINT_CALLS} calls"
