"""Seeded fuzzer over the files cloth-tui reads: mesh files (for `type = "mesh"` objects) and
USD bakes (for `render BAKE` and the replay app), each case a mutation of a good file run in
its own process with a timeout.

    python tools/fuzz_files.py --count 300 --seed 1 --jobs 2 [--keep DIR] [--json]
    python tools/fuzz_files.py --seed 1 --only 17 --keep DIR     # regenerate one case

Mesh cases mutate a closed 80-triangle sphere written as ASCII or binary PLY, OBJ, ASCII or
binary STL, VTK legacy or VTK XML: header counts, face indices and coordinates replaced by
hostile numbers (0, −1, 2³¹, 10¹¹, NaN, …), header lines and property types changed, bytes
flipped, the file cut short or padded; then `simulate SCENE --frames 1` on a scene holding it.
Bake cases mutate a 3-frame bake (.usda text or .usdc binary): the frame rate, any number in
the file (points, radii, time codes), the object attributes' types, the recorded scene, a
line dropped or repeated, a sublayer, reference or payload added (to a FIFO, /dev/zero or
another file), bytes flipped; then `render BAKE -o out.png`.

Each case runs in its own process: a mesh case in a child forked from this one after it has
imported cloth-tui, pyvista and pxr (a fresh interpreter per case cost 10–20 s on a loaded
2-core machine), a bake case (which draws with EGL, not to be set up in a forked copy) in a
fresh `python -m cloth_tui`; --spawn runs every case that way. Either way a crash or a hang
takes only the child, and a child past --timeout is killed.

Each case is classified: ok (exit 0, stderr silent), refused (exit 2, one line on stderr),
bad_message (exit 2, not one line), stderr (exit 0 with output on stderr), timeout, or exit_N
(any other status; a negative N is the signal that killed it). Only ok and refused pass.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MESH_KINDS = ("ply_ascii", "ply_binary", "obj", "stl_ascii", "stl_binary", "vtk", "vtp")
SUFFIX = {"ply_ascii": ".ply", "ply_binary": ".ply", "obj": ".obj", "stl_ascii": ".stl",
          "stl_binary": ".stl", "vtk": ".vtk", "vtp": ".vtp"}
BAKE_KINDS = ("usda", "usdc")
HOSTILE_COUNTS = ["0", "1", "-1", "3", "2147483647", "2147483648", "4294967299",
                  "100000000000", "1" + "0" * 30]
HOSTILE_INDICES = ["0", "-1", "-1000000", "80", "81", "2147483647", "2147483648",
                   "100000000000000000000", "1.5", "nan", "x"]
HOSTILE_NUMBERS = ["0", "-0", "nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "1e300",
                   "-30", "abc", "1" * 400]
PLY_TYPES = ["char", "uchar", "short", "int", "uint", "float", "double", "int64", "list"]


def _sphere():
    import numpy as np
    import pyvista as pv

    s = pv.Icosphere(nsub=1, radius=0.2)
    return np.asarray(s.points, dtype=np.float64), np.asarray(s.regular_faces, dtype=np.int64)


def base_mesh(kind: str, folder: Path) -> bytes:
    """The good file each mesh case mutates: a closed sphere of 80 triangles."""
    import numpy as np

    v, f = _sphere()
    if kind == "ply_ascii" or kind == "ply_binary":
        fmt = "ascii" if kind == "ply_ascii" else "binary_little_endian"
        head = (f"ply\nformat {fmt} 1.0\nelement vertex {len(v)}\nproperty float x\n"
                f"property float y\nproperty float z\nelement face {len(f)}\n"
                "property list uchar int vertex_indices\nend_header\n").encode()
        if kind == "ply_ascii":
            return head + "".join(f"{a:.6f} {b:.6f} {c:.6f}\n" for a, b, c in v).encode() + \
                "".join(f"3 {a} {b} {c}\n" for a, b, c in f).encode()
        face = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        face["n"], face["i"] = 3, f
        return head + v.astype("<f4").tobytes() + face.tobytes()
    if kind == "obj":
        return ("".join(f"v {a:.6f} {b:.6f} {c:.6f}\n" for a, b, c in v) +
                "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f)).encode()
    if kind == "stl_ascii":
        out = ["solid s\n"]
        for tri in f:
            out.append("facet normal 0 0 0\nouter loop\n")
            out += [f"vertex {a:.6f} {b:.6f} {c:.6f}\n" for a, b, c in v[tri]]
            out.append("endloop\nendfacet\n")
        return "".join(out + ["endsolid s\n"]).encode()
    if kind == "stl_binary":
        rec = np.zeros(len(f), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
        rec["v"] = v[f]
        return b"\0" * 80 + len(f).to_bytes(4, "little") + rec.tobytes()
    import pyvista as pv  # VTK's own formats: written by VTK
    path = folder / f"base{SUFFIX[kind]}"
    pv.PolyData.from_regular_faces(v, f).save(path, binary=kind == "vtp")
    return path.read_bytes()


def base_bake(kind: str, folder: Path) -> bytes:
    """The good bake each bake case mutates: 3 frames of the sphere scene, 4×4 particles."""
    path = folder / f"base.{kind}"
    subprocess.run([sys.executable, "-m", "cloth_tui", "bake", "sphere", "-o", str(path),
                    "--frames", "3", "--set", "cloth.resolution=4"], check=True, env=_env(),
                   capture_output=True)
    return path.read_bytes()


# -- mutations ----------------------------------------------------------------------------
def _replace_token(rng, data: bytes, pattern: bytes, values: list[str], where=None) -> bytes:
    """Replace one random match of `pattern` (in data[:where] if given) by a random value."""
    region = data if where is None else data[:where]
    spans = [m.span() for m in re.finditer(pattern, region)]
    if not spans:
        return data
    a, b = rng.choice(spans)
    return data[:a] + rng.choice(values).encode() + data[b:]


def _flip_bytes(rng, data: bytes) -> bytes:
    buf = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        k = rng.randrange(len(buf))
        buf[k] = rng.randrange(256)
    return bytes(buf)


def _lines(rng, data: bytes) -> bytes:
    lines = data.split(b"\n")
    k = rng.randrange(len(lines))
    if rng.random() < 0.5:
        del lines[k]
    else:
        lines.insert(k, lines[rng.randrange(len(lines))])
    return b"\n".join(lines)


def _cut_or_pad(rng, data: bytes) -> bytes:
    if rng.random() < 0.6:
        return data[:rng.randrange(len(data))]
    return data + bytes(rng.randrange(256) for _ in range(rng.randint(1, 200)))


def mutate_mesh(rng: random.Random, kind: str, data: bytes) -> tuple[bytes, str]:
    end = data.find(b"end_header")
    ops = ["flip", "cut_or_pad", "numbers"]
    if kind.startswith("ply"):
        ops += ["count", "count", "type", "header_line"]
    if kind in ("ply_ascii", "obj"):
        ops += ["index", "index", "lines"]
    if kind == "stl_binary":
        ops += ["count"]
    if kind in ("stl_ascii", "vtk"):
        ops += ["lines", "numbers"]
    op = rng.choice(ops)
    if op == "flip":
        return _flip_bytes(rng, data), op
    if op == "cut_or_pad":
        return _cut_or_pad(rng, data), op
    if op == "lines":
        return _lines(rng, data), op
    if op == "count" and kind == "stl_binary":
        n = int(rng.choice(HOSTILE_COUNTS[:8])) % 2**32
        return data[:80] + n.to_bytes(4, "little") + data[84:], op
    if op == "count":
        return _replace_token(rng, data, rb"(?<=element )(\w+ )?\d+",
                              [f"{w} {c}" for w in ("vertex", "face")
                               for c in HOSTILE_COUNTS], end), op
    if op == "type":
        return _replace_token(rng, data, rb"(?<=property )\w+", PLY_TYPES, end), op
    if op == "header_line":
        return _replace_token(rng, data, rb"format \S+|end_header|element \w+",
                              ["format binary_big_endian", "format ascii", "format fancy",
                               "element edge", "", "end_header\nend_header"]), op
    if op == "index":
        if kind == "obj":
            return _replace_token(rng, data, rb"(?<= )\d+(?=[ \n])", HOSTILE_INDICES,
                                  None), op
        body = data.find(b"\n3 ")  # the faces of the ASCII PLY
        tail = data[body:]
        return data[:body] + _replace_token(rng, tail, rb"(?<= )\d+", HOSTILE_INDICES), op
    return _replace_token(rng, data, rb"-?\d+\.\d+", HOSTILE_NUMBERS), "numbers"


def mutate_bake(rng: random.Random, kind: str, data: bytes, folder: Path) -> tuple[bytes, str]:
    if kind == "usdc":
        op = rng.choice(["flip", "flip", "cut_or_pad"])
        return (_flip_bytes(rng, data) if op == "flip" else _cut_or_pad(rng, data)), op
    ops = ["rate", "rate", "number", "number", "number", "attribute", "scene", "lines",
           "arc", "arc", "flip"]
    op = rng.choice(ops)
    if op == "rate":
        return _replace_token(rng, data, rb"(?<=timeCodesPerSecond = )\S+", HOSTILE_NUMBERS),\
            op
    if op == "number":
        return _replace_token(rng, data, rb"-?\d+(\.\d+)?(e-?\d+)?", HOSTILE_NUMBERS), op
    if op == "attribute":
        return _replace_token(rng, data, rb"(custom )?(double3?|string|float3\[\]|uchar\[\]) "
                                         rb"(?=cloth_tui:|points)",
                              ["custom string ", "custom int ", "custom double ",
                               "custom double3 ", "custom bool ", "custom int[] ",
                               "custom token "]), op
    if op == "scene":
        return _replace_token(rng, data, rb'resolution = \d+|object = "\w+"|'
                                         rb'frame_rate = [\d.]+',
                              ["resolution = 5", "resolution = 1000000", 'object = "teapot"',
                               "frame_rate = 0", "frame_rate = 1e300", "[[["]), op
    if op == "lines":
        return _lines(rng, data), op
    if op == "arc":
        target = rng.choice([str(folder / "pipe.usda"), "/dev/zero", str(folder / "other.usda"),
                             "/no/such/file.usda"])
        arc = rng.choice(["sub", "ref", "payload"])
        if arc == "sub":
            return data.replace(b"(\n", f"(\n    subLayers = [@{target}@]\n".encode(), 1), op
        word = "references" if arc == "ref" else "payload"
        return data.replace(b'def Xform "World"', f'def Xform "World" (\n    prepend {word} = '
                                                  f'@{target}@\n)'.encode(), 1), op
    return _flip_bytes(rng, data), op


# -- running ------------------------------------------------------------------------------
def _env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def case_kind(seed: int, index: int) -> str:
    rng = random.Random(f"{seed}-{index}-kind")
    return rng.choice(MESH_KINDS) if rng.random() < 0.6 else rng.choice(BAKE_KINDS)


def make_case(seed: int, index: int, bases: dict, folder: Path) -> tuple[list[str], str, str]:
    """Write case `index`'s file in `folder`; returns (the command's arguments, the kind,
    the mutation)."""
    kind = case_kind(seed, index)
    rng = random.Random(f"{seed}-{index}")
    if kind in MESH_KINDS:
        data, op = mutate_mesh(rng, kind, bases[kind])
        mesh = folder / f"case{SUFFIX[kind]}"
        mesh.write_bytes(data)
        scene = folder / "scene.toml"
        scene.write_text(f'[cloth]\nresolution = 6\n[[objects]]\ntype = "mesh"\n'
                         f'path = "{mesh.name}"\ncenter = [0.0, -0.2, 0.0]\n', encoding="utf-8")
        return ["simulate", str(scene), "--frames", "1", "--json"], kind, op
    os.mkfifo(folder / "pipe.usda")
    (folder / "other.usda").write_bytes(bases["usda"])
    data, op = mutate_bake(rng, kind, bases[kind], folder)
    bake = folder / f"case.{kind}"
    bake.write_bytes(data)
    return ["render", str(bake), "-o", str(folder / "out.png"), "--size", "64x48"], kind, op


# The compile notice is news, not a warning: a cold cache prints it on any run
NOTICE = re.compile(r"cloth-tui: (compiling kernels|\d+ kernels compiled in)")


def classify(code: int | None, err: str) -> str:
    if code is None:
        return "timeout"
    err = "".join(line for line in err.splitlines(keepends=True) if not NOTICE.match(line))
    if code == 0:
        return "stderr" if err.strip() else "ok"
    if code == 2:
        return "refused" if err.count("\n") == 1 and err.endswith("\n") else "bad_message"
    return f"exit_{code}"


def run_one(seed: int, index: int, bases: dict, timeout: float, keep: Path | None) -> dict:
    with tempfile.TemporaryDirectory(prefix="cloth-fuzz-files-") as tmp:
        folder = Path(tmp)
        args, kind, op = make_case(seed, index, bases, folder)
        t0 = time.monotonic()
        try:
            proc = subprocess.run([sys.executable, "-m", "cloth_tui", *args],
                                  capture_output=True, text=True, timeout=timeout, env=_env(),
                                  cwd=tmp, stdin=subprocess.DEVNULL)
            code, err = proc.returncode, proc.stderr
        except subprocess.TimeoutExpired:
            code, err = None, ""
        return _result(seed, index, kind, op, code, err, time.monotonic() - t0, folder, keep)


def _child(args: list[str], folder: Path, fresh: bool) -> None:
    """In a forked child: run the command as `python -m cloth_tui` would (`fresh`: exec that),
    its output to files."""
    try:
        os.chdir(folder)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        for fd, name in ((1, "stdout"), (2, "stderr")):
            out = os.open(folder / name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            os.dup2(out, fd)
        if fresh:
            os.execve(sys.executable, [sys.executable, "-m", "cloth_tui", *args], _env())
        from cloth_tui.cli import main
        code = main(args)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    except BaseException:  # noqa: BLE001 - anything escaping main() is an exit 1
        os._exit(1)


def run_forked(seed: int, indices: list[int], bases: dict, timeout: float, jobs: int,
               keep: Path | None):
    """Yield run_one's results, up to `jobs` forked children at once (main thread only)."""
    sys.path.insert(0, str(ROOT))
    for module in ("cloth_tui.cli", "cloth_tui.meshes", "cloth_tui.mesh_files",
                   "cloth_tui.io.usd_read", "cloth_tui.render.replay", "cloth_tui.sim.run.runner",
                   "pyvista", "pxr.Usd"):
        __import__(module)
    todo, running = list(indices), {}
    while todo or running:
        while todo and len(running) < max(1, jobs):
            index = todo.pop(0)
            tmp = tempfile.TemporaryDirectory(prefix="cloth-fuzz-files-")
            args, kind, op = make_case(seed, index, bases, Path(tmp.name))
            sys.stdout.flush()
            sys.stderr.flush()
            pid = os.fork()
            if pid == 0:
                _child(args, Path(tmp.name), fresh=kind in BAKE_KINDS)
            running[pid] = (index, kind, op, tmp, time.monotonic())
        time.sleep(0.05)
        for pid, (index, kind, op, tmp, t0) in list(running.items()):
            done, status = os.waitpid(pid, os.WNOHANG)
            late = not done and time.monotonic() - t0 > timeout
            if late:
                os.kill(pid, 9)
                os.waitpid(pid, 0)
            elif not done:
                continue
            del running[pid]
            folder = Path(tmp.name)
            code = None if late else os.waitstatus_to_exitcode(status)
            err = "" if late else (folder / "stderr").read_text("utf-8", "replace")
            yield _result(seed, index, kind, op, code, err, time.monotonic() - t0, folder,
                          keep)
            tmp.cleanup()


def _result(seed, index, kind, op, code, err, seconds, folder: Path, keep) -> dict:
    verdict = classify(code, err)
    if keep is not None and verdict not in ("ok", "refused"):
        keep.mkdir(parents=True, exist_ok=True)
        for path in folder.iterdir():
            if path.is_file() and path.name.startswith(("case", "scene", "stderr")):
                (keep / f"{seed}-{index}-{path.name}").write_bytes(path.read_bytes())
    return {"index": index, "kind": kind, "mutation": op, "class": verdict, "exit": code,
            "seconds": round(seconds, 1),
            "stderr": err.strip().splitlines()[-1][:300] if err.strip() else ""}


def make_bases(folder: Path, kinds) -> dict:
    bases = {k: base_mesh(k, folder) for k in kinds if k in MESH_KINDS}
    if any(k in BAKE_KINDS for k in kinds):
        bases |= {k: base_bake(k, folder) for k in BAKE_KINDS}
    return bases


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=20, help="cases to run")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--only", type=int, help="run only case INDEX of this seed")
    p.add_argument("--jobs", type=int, default=2, help="processes at once")
    p.add_argument("--timeout", type=float, default=60.0, help="seconds per case")
    p.add_argument("--keep", type=Path, help="copy the files of each failing case here")
    p.add_argument("--json", action="store_true", help="one JSON object per case on stdout")
    p.add_argument("--spawn", action="store_true",
                   help="a fresh interpreter per case instead of a forked child")
    args = p.parse_args(argv)
    indices = [args.only] if args.only is not None else list(range(args.count))
    counts: dict[str, int] = {}
    failures = 0
    with tempfile.TemporaryDirectory(prefix="cloth-fuzz-bases-") as tmp:
        bases = make_bases(Path(tmp), {case_kind(args.seed, i) for i in indices})
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = (pool.map(lambda i: run_one(args.seed, i, bases, args.timeout, args.keep),
                                indices) if args.spawn else
                       run_forked(args.seed, indices, bases, args.timeout, args.jobs, args.keep))
            for r in results:
                counts[r["class"]] = counts.get(r["class"], 0) + 1
                failures += r["class"] not in ("ok", "refused")
                print(json.dumps(r) if args.json else
                      f"{r['index']:5d} {r['kind']:<10} {r['mutation']:<11} {r['class']:<11} "
                      f"{r['seconds']:5.1f}s {r['stderr'][:90]}", flush=True)
    print(f"seed {args.seed}, {len(indices)} cases: " +
          ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
