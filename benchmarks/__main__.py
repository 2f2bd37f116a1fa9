"""``make bench``: run every benchmark, print its figures, keep them in RESULTS.md.

Each ``bench_*`` module has a ``main()`` that prints its own figures and returns
them as a dict. This runner records the current run at the top of RESULTS.md and
keeps the previous run below it, so a change's effect is visible in one file.

    python -m benchmarks                 # all
    python -m benchmarks arap bbw        # some
    python -m benchmarks --refresh bbw   # rerun some, replace their sections in the latest run

``--refresh`` keeps the latest run and its predecessor, replaces (or adds) the
named benchmarks' sections in the latest run and notes when they were taken:
one benchmark can be measured again without rerunning the whole suite.
"""

from __future__ import annotations

import datetime
import importlib
import json
import platform
import sys
import time
from pathlib import Path

ORDER = ("arap", "arap_demo", "bbw", "fast", "lbs", "notebooks", "grading", "scale", "collusion")
RESULTS = Path(__file__).with_name("RESULTS.md")
MARK = "<!-- previous run -->"


def _fmt(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, dict):
        return json.dumps(value, default=str)
    return str(value)


def _section(figures: dict[str, dict], started: str) -> str:
    lines = [f"## Run of {started}", "", f"Machine: {platform.machine()}, {platform.python_version()}, "
             f"{__import__('os').cpu_count()} cores.", ""]
    for name, figs in figures.items():
        lines += [f"### {name}", "", "| figure | value |", "|---|---|"]
        lines += [f"| {k} | {_fmt(v)} |" for k, v in figs.items()]
        lines.append("")
    return "\n".join(lines)


def _refreshed(text: str, figures: dict[str, dict], started: str) -> str:
    """``text`` (RESULTS.md) with the latest run's sections of ``figures`` replaced or added."""
    head, sep, previous = text.partition(MARK)
    for name, figs in figures.items():
        section = _section({name: figs}, started).split("\n", 4)[4]  # without the run's heading
        # the other sections may have seen another load: say when, and how busy the machine was
        note = (f"Re-measured alone at {started} (`python -m benchmarks --refresh {name}`), "
                f"load average {__import__('os').getloadavg()[0]:.1f} on {__import__('os').cpu_count()} cores afterwards.")
        section = section.replace("\n", f"\n\n{note}\n", 1).rstrip("\n") + "\n\n"
        start = head.find(f"\n### {name}\n")
        if start < 0:
            head = head.rstrip("\n") + "\n\n" + section
        else:
            end = head.find("\n### ", start + 1)
            head = head[:start + 1] + section + (head[end + 1:] if end >= 0 else "")
    return head.rstrip("\n") + "\n" + (f"\n{sep}{previous}" if sep else "")


def main(argv: list[str]) -> int:
    refresh = "--refresh" in argv
    argv = [a for a in argv if a != "--refresh"]
    if refresh and not (argv and RESULTS.is_file() and "## Run of" in RESULTS.read_text()):
        print("--refresh needs benchmark names and a RESULTS.md with a run to refresh", file=sys.stderr)
        return 2
    names = argv or list(ORDER)
    unknown = [n for n in names if n not in ORDER]
    if unknown:
        print(f"unknown benchmark(s) {unknown}; choose from {list(ORDER)}", file=sys.stderr)
        return 2
    started = datetime.datetime.now().isoformat(timespec="seconds")
    figures: dict[str, dict] = {}
    for name in names:
        print(f"\n=== benchmark: {name} ===", flush=True)
        t0 = time.perf_counter()
        figures[name] = dict(importlib.import_module(f"benchmarks.bench_{name}").main())
        figures[name]["benchmark wall time (s)"] = time.perf_counter() - t0
    if refresh:
        RESULTS.write_text(_refreshed(RESULTS.read_text(), figures, started))
        print(f"\nsections {names} replaced in {RESULTS}")
        return 0
    previous = ""
    if RESULTS.is_file():
        text = RESULTS.read_text()
        if "## Run of" in text:
            previous = text[text.index("## Run of"):].split(MARK)[0].strip()
    RESULTS.write_text(
        "# Benchmark results\n\nWritten by `make bench` (`python -m benchmarks`); the run before it is kept below.\n\n"
        + _section(figures, started)
        + (f"\n{MARK}\n\n# Previous run\n\n{previous}\n" if previous else "")
    )
    print(f"\nfigures written to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
