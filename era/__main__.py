"""Command line of the library: ``python3 -m era campaign FILES... --out table.csv`` (scripted campaigns).

Run ``python3 -m era campaign --help`` for the options.
"""

from __future__ import annotations

import argparse
import sys

from . import __version__
from .errors import EraError
from .words import counted


def _orders(text: str) -> range:
    """'2:80:2' → range(2, 81, 2) (the last order included)."""
    try:
        parts = [int(p) for p in text.split(":")]
        first, last, step = (parts + [2])[:3] if len(parts) >= 2 else (2, parts[0], 2)
        if first < 1 or last < first or step < 1:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(f"orders are FIRST:LAST[:STEP], e.g. 2:80:2, got {text!r}") from None
    return range(first, last + 1, step)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python3 -m era", description="ERA modal analysis from the command line.")
    parser.add_argument("--version", action="version", version=f"era {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser("campaign", help="identify every record the same way and track the modes through them",
                       description="Identify every record (UFF, CSV or NPZ; one record per file) with the app's "
                                   "defaults and follow each mode through the records. Times come from the file "
                                   "names (e.g. rec_2026-03-02T05-00.csv) or their order. Writes one row per record "
                                   "and tracked mode.")
    c.add_argument("files", nargs="+", help="record files, or folders of them (their files in name order)")
    c.add_argument("--out", required=True, help="CSV table to write (record, name, time, mode, found, frequency_hz, "
                                                "damping_ratio, mac_to_reference, emac, mpc, ...)")
    c.add_argument("--modes-out", help="CSV of the tracked modes (reference frequency, origin, records found)")
    c.add_argument("--kind", default="auto", choices=("auto", "ambient", "decay", "pulse", "frf", "io"),
                   help="how a record becomes Markov parameters (ambient: NExT); default: guessed per file")
    c.add_argument("--dt", type=float, help="sampling interval in s for CSV files without a time column")
    c.add_argument("--rows", type=int, help="Hankel block rows (default: suggested per record)")
    c.add_argument("--cols", type=int, help="Hankel block columns (default: suggested per record)")
    c.add_argument("--orders", type=_orders, default=range(2, 81, 2), help="model orders FIRST:LAST[:STEP] of "
                                                                           "each diagram (default 2:80:2)")
    c.add_argument("--workers", type=int, help="local processes (default one per core; 0: in this process)")
    c.add_argument("--scheduler", help="address of a Dask scheduler (tcp://host:8786) to run the records on")
    c.add_argument("--cache-dir", help="folder that keeps each analysed record, so a re-run resumes")
    c.add_argument("--quiet", action="store_true", help="no progress on stderr")
    return parser


def campaign(args) -> int:
    from .campaign import run_campaign

    def progress(done, total):
        if not args.quiet:
            print(f"\r{done}/{total} records", end="" if done < total else "\n", file=sys.stderr, flush=True)

    result = run_campaign(args.files, kind=args.kind, dt=args.dt, rows=args.rows, cols=args.cols, orders=args.orders,
                          client=args.scheduler, progress=progress, cache_dir=args.cache_dir, workers=args.workers)
    result.table.to_csv(args.out, index=False)
    if args.modes_out:
        result.modes_frame().to_csv(args.modes_out, index=False)
    n_ok = len(result.records)
    print(f"{counted(n_ok, 'record')} analysed, {len(result.failed)} failed, "
          f"{counted(len(result.modes), 'tracked mode')}; "
          f"table written to {args.out}", file=sys.stderr)
    for f in result.failed:
        print(f"failed: {f.name}: {f.reason}", file=sys.stderr)
    return 0 if n_ok else 1


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    try:
        return campaign(args)
    except EraError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
