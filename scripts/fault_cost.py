#!/usr/bin/env python3
"""What fresh memory costs on this machine: 4 KiB pages against transparent huge pages (issue 19).

A single render's first frame takes some 100 MB of fresh memory (textures, cube maps, frame
targets), which the kernel maps on first touch. What that costs is the machine's, not the
renderer's: 1.7-2 us a 4 KiB page on the virtual machines of the earlier sessions, 10.1-11.3 us
on another (docs/performance.md, "Huge pages where 4 KiB faults are dear"), where the same 2
MiB in one huge page took 0.12-0.15 ms, or 1.2-3.7 ms where the host had to back it again. The
memory warm-up (cli/memory_warmup.h, cli/huge_page_trial.h) chooses between the two by the same
measure. Run this beside a benchmark to read its first frames.

Each round maps `--mb` MiB of anonymous memory twice, advised MADV_NOHUGEPAGE and then
MADV_HUGEPAGE, writes one byte per 4 KiB page and unmaps it, and prints the time per 4 KiB page
and per 2 MiB huge page. The first huge-page round of a process often pays for the host's
backing; the later ones show what memory just handed back costs.

Usage: scripts/fault_cost.py [--mb 64] [--rounds 3]"""
import argparse, ctypes, mmap, time

PAGE = 4096
HUGE = 2 << 20


def touch(size, advice):
    m = mmap.mmap(-1, size + HUGE, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    try:
        # A 2 MiB-aligned start, so that huge pages can back the whole range.
        base = -_address(m) % HUGE
        m.madvise(advice, base, size)
        start = time.perf_counter()
        for offset in range(base, base + size, PAGE):
            m[offset] = 1
        return (time.perf_counter() - start) * 1e3
    finally:
        m.close()


def _address(m):
    first = ctypes.c_char.from_buffer(m)
    address = ctypes.addressof(first)
    del first  # an exported buffer would keep the mapping from closing
    return address


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    size = a.mb << 20
    if not hasattr(mmap, "MADV_HUGEPAGE"):
        raise SystemExit("fault_cost: this Python's mmap has no MADV_HUGEPAGE")
    print("| round | 4 KiB pages: ms | us per page | huge pages: ms | ms per 2 MiB |")
    print("|---:|---:|---:|---:|---:|")
    for r in range(1, a.rounds + 1):
        small = touch(size, mmap.MADV_NOHUGEPAGE)
        huge = touch(size, mmap.MADV_HUGEPAGE)
        print(f"| {r} | {small:.1f} | {small * 1e3 / (size // PAGE):.2f} | {huge:.1f} | "
              f"{huge / (size // HUGE):.2f} |")
    print(f"\n{a.mb} MiB a round, one byte written per 4 KiB page (Python's loop adds about 0.1 us "
          "a page).")


if __name__ == "__main__":
    main()
