"""Memory after a fit on worker processes: it returns to what it was before.

Run: ``PYTHONPATH=src python benchmarks/bench_memory.py [n_demos] [n_fits]``.

Fits ``KeypointHMM(n_jobs=2)`` on short synthetic demonstrations (they go to
worker processes, ``ndlfd._parallel``) several times in one process, and
prints the resident set size (RSS) of this process and of all its children:

* ``before``: after a warm-up fit on one thread (imports, compiled kernels
  and caches loaded, so what is measured is the fit, not the first import);
* ``during``: the largest total seen while the fits run (sampled every 20 ms
  by a thread), with the number of worker processes seen;
* ``after``: when the last fit has returned (worker processes are ended by
  the fit itself);
* ``after shutdown``: after ``ndlfd.shutdown()`` and a garbage collection.

Target (issue 18): ``after`` within 20 MiB of ``before``, and no worker
process left. The exit status is 1 when the target is missed.
"""

import gc
import sys
import threading
import time

import psutil

import ndlfd
from ndlfd import KeypointHMM, synth

TARGET_MIB = 20.0


def rss_mib(proc: psutil.Process) -> tuple[float, float, int]:
    """RSS of ``proc``, of ``proc`` with its live children, and their count."""
    own = proc.memory_info().rss
    total, n = own, 0
    for child in proc.children(recursive=True):
        try:
            total += child.memory_info().rss
            n += 1
        except psutil.NoSuchProcess:  # ended while we looked
            pass
    return own / 2**20, total / 2**20, n


class Sampler(threading.Thread):
    """The largest total RSS and child count while the fits run."""

    def __init__(self, proc: psutil.Process) -> None:
        super().__init__(daemon=True)
        self.proc, self.peak, self.children = proc, 0.0, 0
        self.stop = threading.Event()

    def run(self) -> None:
        while not self.stop.wait(0.02):
            _, total, n = rss_mib(self.proc)
            self.peak = max(self.peak, total)
            self.children = max(self.children, n)


def main(n_demos: int = 400, n_fits: int = 3) -> int:
    proc = psutil.Process()
    train, _ = synth.make_dataset("square", n_demos=n_demos, random_state=0)
    KeypointHMM(epsilon=0.05, n_time_bins=30, n_jobs=1).fit(train)  # warm-up
    gc.collect()
    own0, total0, kids0 = rss_mib(proc)

    sampler = Sampler(proc)
    sampler.start()
    t0 = time.perf_counter()
    for _ in range(n_fits):
        model = KeypointHMM(epsilon=0.05, n_time_bins=30, n_jobs=2).fit(train)
    seconds = time.perf_counter() - t0
    sampler.stop.set()
    sampler.join()
    del model
    gc.collect()
    own1, total1, kids1 = rss_mib(proc)
    ndlfd.shutdown()
    gc.collect()
    own2, total2, kids2 = rss_mib(proc)

    print(f"{n_fits} fits of {n_demos} demonstrations with n_jobs=2 in {seconds:.1f} s")
    print("                 this process   with children   worker processes")
    print(f"before           {own0:9.1f} MiB   {total0:9.1f} MiB   {kids0:5d}")
    print(
        f"during (peak)    {'':>13}   {sampler.peak:9.1f} MiB   {sampler.children:5d}"
    )
    print(f"after            {own1:9.1f} MiB   {total1:9.1f} MiB   {kids1:5d}")
    print(f"after shutdown   {own2:9.1f} MiB   {total2:9.1f} MiB   {kids2:5d}")
    growth = total1 - total0
    ok = growth <= TARGET_MIB and kids1 == 0
    print(
        f"growth after the fits {growth:+.1f} MiB (target within {TARGET_MIB:.0f}"
        f" MiB, no worker left): {'met' if ok else 'MISSED'}"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    sys.exit(main(*args))
