"""Motion or analysis for a collection larger than one machine, on a Dask cluster.

Maps the ``violin_skeleton`` package over a list of audio/MIDI files: each worker process
loads the models once (one ``Pipeline`` per process, kept between tasks), writes every output
atomically beside its target (a temporary file renamed into place), and the driver writes a
failure list. Outputs mirror the input paths relative to ``--root``.

Local cluster of 2 workers (what the tests run)::

    python dask_batch.py --files list.txt --root /data/takes --out /data/motion --local 2

A real cluster: start a scheduler (``dask scheduler``) and workers on every machine
(``dask worker tcp://scheduler:8786 --nthreads 1 --nworkers 2``), each with
``pip install violin-skeleton`` and the input files at the same paths (a shared file system
or object storage mounted at one path), then::

    python dask_batch.py --files list.txt --root /data/takes --out /data/motion \
        --scheduler tcp://scheduler:8786

``--skip-existing`` resumes an interrupted run. The run exits 1 when any file failed; the
failures (file and reason) are in ``OUT/failures.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

_PIPELINE = None


def _pipeline():
    """The worker process's pipeline, created on its first task (models loaded once)."""
    global _PIPELINE
    if _PIPELINE is None:
        import violin_skeleton

        _PIPELINE = violin_skeleton.Pipeline()
    return _PIPELINE


def output_for(path: str, root: str, out: str, kind: str, fmt: str) -> str:
    """Where the output of ``path`` goes: its path under ``root``, mirrored under ``out``."""
    rel = Path(os.path.relpath(path, root))
    ext = "json" if kind == "analyze" else fmt
    return str(Path(out) / rel.parent / f"{rel.stem}.{ext}")


def _atomic_save(target: str, save) -> None:
    """Calls ``save(tmp_path)`` on a temporary file beside ``target`` and renames it."""
    parent = os.path.dirname(target) or "."
    os.makedirs(parent, exist_ok=True)
    suffix = os.path.splitext(target)[1]
    fd, tmp = tempfile.mkstemp(dir=parent, prefix=".dask-batch-", suffix=suffix)
    os.close(fd)
    try:
        save(tmp)
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def process(path: str, target: str, kind: str, fmt: str, skip_existing: bool) -> dict:
    """One task: analyse or generate ``path`` into ``target``; never raises."""
    if skip_existing and os.path.exists(target):
        return {"file": path, "status": "skipped"}
    try:
        os.makedirs(os.path.dirname(target) or ".", exist_ok=True)
        pipeline = _pipeline()
        # Both saves are atomic (a temporary file beside the target, renamed into place).
        if kind == "analyze":
            pipeline.analyze(path).save(target)
        else:
            pipeline.generate(path).save(target, format=fmt)
        return {"file": path, "status": "written", "output": target}
    except Exception as e:  # a failed file is reported, the batch goes on
        return {"file": path, "status": "failed", "error": f"{type(e).__name__}: {e}"}


def run(files, root, out, kind="generate", fmt="json", client=None, skip_existing=False):
    """Maps :func:`process` over ``files`` on ``client``; returns the per-file results and
    writes ``out/failures.json``."""
    targets = [output_for(f, root, out, kind, fmt) for f in files]
    futures = client.map(
        process,
        files,
        targets,
        kind=kind,
        fmt=fmt,
        skip_existing=skip_existing,
        pure=False,
    )
    results = client.gather(futures)
    failures = [r for r in results if r["status"] == "failed"]
    os.makedirs(out, exist_ok=True)
    _atomic_save(
        os.path.join(out, "failures.json"),
        lambda tmp: Path(tmp).write_text(json.dumps(failures, indent=2)),
    )
    return results


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", required=True, help="a text file with one input path per line")
    ap.add_argument("--root", required=True, help="the folder the input paths are under")
    ap.add_argument("--out", required=True, help="the output folder")
    ap.add_argument("--kind", choices=["generate", "analyze"], default="generate")
    ap.add_argument("--format", default="json", choices=["json", "csv", "npy", "bvh"])
    ap.add_argument("--skip-existing", action="store_true")
    where = ap.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", help="address of a running Dask scheduler")
    where.add_argument("--local", type=int, metavar="N", help="start a local cluster of N workers")
    args = ap.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    files = [ln.strip() for ln in Path(args.files).read_text().splitlines() if ln.strip()]
    if args.local:
        cluster = LocalCluster(n_workers=args.local, threads_per_worker=1, processes=True)
        client = Client(cluster)
    else:
        cluster = None
        client = Client(args.scheduler)
    try:
        results = run(files, args.root, args.out, args.kind, args.format, client, args.skip_existing)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    counts = {s: sum(r["status"] == s for r in results) for s in ("written", "skipped", "failed")}
    print(
        f"{len(files)} files: {counts['written']} written, {counts['skipped']} skipped, "
        f"{counts['failed']} failed (listed in {os.path.join(args.out, 'failures.json')})",
        file=sys.stderr,
    )
    for r in results:
        if r["status"] == "failed":
            print(f"failed: {r['file']}: {r['error']}", file=sys.stderr)
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
