#!/usr/bin/env python3
"""`harmonia atlas` beside glTF-Transform's `unwrap` (xatlas compiled to WebAssembly: watlas) on the
public glTF assets, both outputs scored by one independent code path.

Usage (after the build; Debian's python, standard library only; about 2-3 minutes on 2 cores):
  /usr/bin/python3 bench/gltf_unwrap_peer.py [--gltf-transform PATH] [--harmonia build/harmonia]
      [--assets DIR] [--group mesh|primitive] [--resolution 1024] [--padding 2] [--repeat 3]
      [--no-peer-pack] [--only A.glb,B.gltf] [--keep DIR] [--out-md FILE] [--out-json FILE]

The peer: the `gltf-transform` CLI (npm `@gltf-transform/cli`), found by --gltf-transform, else
$GLTF_TRANSFORM, else `gltf-transform` on PATH (node >= 18 on PATH, or $NODE). Install it into a
scratch prefix with
  npm install --prefix /tmp/gtpeer @gltf-transform/cli
  export GLTF_TRANSFORM=/tmp/gtpeer/node_modules/.bin/gltf-transform
Its command is `gltf-transform unwrap IN OUT --texcoord N --group-by mesh|primitive|scene`
(default mesh, as harmonia's --group). unwrapPrimitives() adds each primitive of a group to one
xatlas Atlas and calls `atlas.generate()` with no options, i.e. xatlas's defaults: ChartOptions
default, PackOptions resolution 0, texelsPerUnit 0, padding 0, bilinear true. xatlas then
estimates texelsPerUnit for a 1024 atlas at 75 % use from the charts' area, clamped to at most
1024 texels per unit, so its atlas is W x H near 1024 on big meshes but tiny (7x7 ... 100x100)
on meshes of less than ~0.75 units^2, and never square; the CLI has no resolution or padding
option. With N > 0 it hands TEXCOORD_0 to xatlas too (MeshDecl.vertexUvData: the existing UV
seams become chart boundaries); harmonia's charts ignore the existing UVs (no --keep-splits).
It cannot take triangle strips or fans (modes 5, 6: it gives the strip's indices to xatlas as a
list and fails); it writes EXT_meshopt_compression input out uncompressed.

Per asset of --assets (default ../shared/data/gltf, or $HARMONIA_SHARED_DATA/gltf):
- harmonia: `harmonia atlas IN OUT.glb --resolution R --padding P --group G --json`: each
  primitive's new UVs go to the lowest set it lacks.
- peer: `gltf-transform unwrap IN OUT.glb --texcoord N --group-by G` (row `gltf-transform`), N
  the largest of those lowest missing sets over the primitives (one set for the whole file; the
  peer fills the lower missing sets with the same UVs, so every primitive is scored on its lowest
  missing set in both outputs). It is timed plain, then run once more, untimed, under a
  `node --import` hook that wraps watlas' Atlas.generate to log each atlas' W x H, atlas count
  and generate time (the file is checked to be byte-identical to the timed run's). Unless
  --no-peer-pack a row `gltf-transform +pack` runs the same CLI under the hook passing
  PackOptions {resolution: R, padding: P} to generate: the nearest the peer gets to harmonia's
  texel budget (with texelsPerUnit 0 xatlas still only estimates the scale and packs one atlas of
  its own W x H). When the peer fails on an asset with strips, rows `(lists)` run it on a copy
  whose strips and fans the peer's own convertPrimitiveToTriangles turned into lists (untimed).
- Time: wall time of the whole command (process start, file read and write; for the peer node's
  start and the WebAssembly set-up too), the best of --repeat runs (one run when the first takes
  over 10 s). `core s`: the tool's own figure of its atlas computation: harmonia's report
  (`seconds` summed over its atlases, of the best run); the peer's watlas generate() time summed
  over its atlases, from the hook's run.
- Scoring, the same code for every output: the file is read with ../shared/tools/gltfread.py (an
  output still under EXT_meshopt_compression or Draco would first be decoded with the peer's own
  @gltf-transform/core + meshoptimizer / draco3dgltf, the extension dropped, nothing else changed);
  every atlas (per mesh or per primitive, as grouped) is written as an OBJ: POSITION of its
  primitives (mesh frame, as both tools saw them) and per-corner vt = the new set with
  v_obj = 1 - v_gltf, vertices and vts welded by exact value within the atlas (a vt per distinct
  (position, uv)), no chart groups; then `atlaseval.py OBJ OBJ --res WxH` with harmonia's R x R
  and the peer's own W x H from the hook's log. Charts are thus atlaseval's connected components
  of shared vts for both tools.
- Columns: charts (summed over the asset's atlases), atlas size(s), coverage (atlaseval's:
  covered texel centres / W H; mean over atlases), cov. sq (covered / max(W, H)^2: the share of a
  square atlas), L2 (Sander L2 stretch, 3D-area-weighted over the atlases), flips (atlaseval's:
  minority-orientation plus zero-area UV triangles; the latter in parentheses), overlapping
  texels, chart-boundary crossings (between and within charts), valid (atlaseval's verdict on
  every atlas), time s, core s. Notes below the table: what differed between the tools' inputs,
  compression, xatlas' atlas counts, and harmonia's own chart count where atlaseval's differs.
"""

import argparse
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

SOURCE = pathlib.Path(__file__).resolve().parents[1]
SHARED = pathlib.Path(os.environ.get("HARMONIA_SHARED_DATA", "")).parent if os.environ.get(
    "HARMONIA_SHARED_DATA") else SOURCE.parent / "shared"
TOOLS = SHARED / "tools"
sys.path.insert(0, str(TOOLS))
import gltfread  # noqa: E402

INSTALL = ("the peer is missing: install glTF-Transform's CLI into a scratch prefix and point at it:\n"
           "  npm install --prefix /tmp/gtpeer @gltf-transform/cli\n"
           "  export GLTF_TRANSFORM=/tmp/gtpeer/node_modules/.bin/gltf-transform\n"
           "(or pass --gltf-transform PATH; node >= 18 on PATH)")

HOOK = r"""
import { appendFileSync } from 'node:fs';
const w = await import(process.env.WATLAS_URL);
const orig = w.Atlas.prototype.generate;
const pack = process.env.WATLAS_PACK ? JSON.parse(process.env.WATLAS_PACK) : null;
w.Atlas.prototype.generate = function (chartOptions = {}, packOptions = {}) {
  if (pack) packOptions = { ...packOptions, ...pack };
  const t0 = performance.now();
  orig.call(this, chartOptions, packOptions);
  const t1 = performance.now();
  if (process.env.WATLAS_LOG) {
    const meshes = [];
    for (let i = 0; i < this.meshCount; i++) {
      const m = this.getMesh(i);
      meshes.push([m.vertexCount, m.indexCount, m.chartCount]);
    }
    appendFileSync(process.env.WATLAS_LOG, JSON.stringify({ width: this.width, height: this.height,
      atlasCount: this.atlasCount, chartCount: this.chartCount, texelsPerUnit: this.texelsPerUnit,
      ms: t1 - t0, pack: packOptions, meshes }) + '\n');
  }
};
"""

# The peer's own libraries on a file, for preparation only (never timed, never scoring):
#   decompress: decode EXT_meshopt_compression / Draco and drop the extension (nothing else changed);
#   triangulate: strips and fans (modes 5, 6) as triangle lists (convertPrimitiveToTriangles), which the
#                peer's unwrap cannot take (it hands the strip's indices to xatlas as a list).
PREPARE = r"""
import { createRequire } from 'node:module';
import { pathToFileURL } from 'node:url';
const req = createRequire(process.env.PEER_CLI);
const core = req('@gltf-transform/core');
const ext = req('@gltf-transform/extensions');
const fn = req('@gltf-transform/functions');
const mo = await import(pathToFileURL(req.resolve('meshoptimizer')).href);
const draco3d = req('draco3dgltf');
await mo.MeshoptDecoder.ready;
await mo.MeshoptEncoder.ready;
const io = new core.NodeIO().registerExtensions(ext.ALL_EXTENSIONS).registerDependencies({
  'meshopt.decoder': mo.MeshoptDecoder, 'meshopt.encoder': mo.MeshoptEncoder,
  'draco3d.decoder': await draco3d.createDecoderModule(), 'draco3d.encoder': await draco3d.createEncoderModule() });
const [mode, input, output] = process.argv.slice(2);
const doc = await io.read(input);
if (mode === 'decompress') {
  for (const e of doc.getRoot().listExtensionsUsed())
    if (e.extensionName === 'EXT_meshopt_compression' || e.extensionName === 'KHR_draco_mesh_compression') e.dispose();
} else if (mode === 'triangulate') {
  for (const m of doc.getRoot().listMeshes())
    for (const p of m.listPrimitives())
      if (p.getMode() === 5 || p.getMode() === 6) fn.convertPrimitiveToTriangles(p);
} else throw new Error('mode: ' + mode);
if (doc.getRoot().listBuffers().length > 1) await doc.transform(fn.unpartition());  // a GLB holds one buffer
await io.write(output, doc);
"""


PEER_INFO = r"""
const { createRequire } = require('node:module');
const fs = require('node:fs'), path = require('node:path');
const req = createRequire(process.env.PEER_CLI);
function version(name) {
  let d = path.dirname(req.resolve(name));
  while (d !== path.dirname(d)) {
    const p = path.join(d, 'package.json');
    if (fs.existsSync(p)) { const j = JSON.parse(fs.readFileSync(p)); if (j.name === name) return [j.version, req.resolve(name)]; }
    d = path.dirname(d);
  }
  return [null, null];
}
const cli = JSON.parse(fs.readFileSync(path.join(path.dirname(process.env.PEER_CLI), '..', 'package.json')));
const [wv, wpath] = version('watlas');
const [fv] = version('@gltf-transform/functions');
console.log(JSON.stringify({ cli: cli.version, functions: fv, watlas: wv, watlas_path: wpath, node: process.version }));
"""


def find_peer(arg):
    cand = arg or os.environ.get("GLTF_TRANSFORM") or shutil.which("gltf-transform")
    if not cand or not os.path.exists(cand):
        sys.exit(INSTALL + ("\n(not found: %s)" % cand if cand else ""))
    return os.path.realpath(cand)  # .../@gltf-transform/cli/bin/cli.js


def run_timed(cmd, env=None, timeout=600):
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    return time.perf_counter() - t, p


def input_texcoord(j):
    """Per mesh, per primitive: the set harmonia's default picks (the lowest the primitive lacks); the largest of
    them (the peer's --texcoord: one set for the whole file); the primitives that already have that one."""
    sets = []
    for m in j.get("meshes", []):
        row = []
        for p in m["primitives"]:
            n = 0
            while "TEXCOORD_%d" % n in p["attributes"]:
                n += 1
            row.append(n)
        sets.append(row)
    best = max((n for row in sets for n in row), default=0)
    clash = sum(1 for m in j.get("meshes", []) for p in m["primitives"] if "TEXCOORD_%d" % best in p["attributes"])
    return sets, best, clash


def has_strips(j):
    return any(p.get("mode", 4) in (5, 6) for m in j.get("meshes", []) for p in m["primitives"])


def is_compressed(j):
    return "EXT_meshopt_compression" in j.get("extensionsUsed", []) or \
        "KHR_draco_mesh_compression" in j.get("extensionsUsed", [])


def tri_area(a, b, c):
    ux, uy, uz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    vx, vy, vz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    return 0.5 * math.sqrt((uy * vz - uz * vy) ** 2 + (uz * vx - ux * vz) ** 2 + (ux * vy - uy * vx) ** 2)


def write_atlases(path, sets, group, folder, tag):
    """One OBJ per atlas of the glTF output (primitive (m, p) read from its set TEXCOORD_sets[m][p]):
    [(obj path, 3D area, faces, distinct _CHART values or None)]."""
    j, bufs = gltfread.load(str(path))
    meshes = gltfread.triangles(j, bufs)
    groups = []
    for mi, prims in enumerate(meshes):
        for pi, p in enumerate(prims):
            sem = "TEXCOORD_%d" % sets[mi][pi]
            if not p.get("compressed") and p["corners"] and sem not in p["attributes"]:
                raise RuntimeError("%s: meshes[%d].primitives[%d] has no %s" % (path.name, mi, pi, sem))
        have = [(pi, p) for pi, p in enumerate(prims) if not p.get("compressed") and p["corners"]]
        if any(p.get("compressed") for p in prims):
            raise RuntimeError("%s: mesh %d still compressed" % (path, mi))
        if group == "mesh":
            if have:
                groups.append(("m%d" % mi, have))
        else:
            groups.extend(("m%dp%d" % (mi, pi), [(pi, p)]) for pi, p in have)
    out = []
    for name, prims in groups:
        vid, tid = {}, {}
        faces = []
        area = 0.0
        charts = set()
        has_chart = True
        for pi, p in prims:
            P = p["attributes"]["POSITION"]
            U = p["attributes"]["TEXCOORD_%d" % sets[int(name[1:].split("p")[0])][pi]]
            C = p["attributes"].get("_CHART")
            if C is None:
                has_chart = False
            keys = []
            for k in range(len(P)):
                pos = tuple(float(x) for x in P[k][:3])
                uv = (float(U[k][0]), 1.0 - float(U[k][1]))
                v = vid.setdefault(pos, len(vid))
                t = tid.setdefault((pos, uv), len(tid))
                keys.append((v, t))
            for a, b, c in p["corners"]:
                faces.append((keys[a], keys[b], keys[c]))
                area += tri_area(P[a], P[b], P[c])
                if C is not None:
                    charts.add(C[a][0])
        obj = folder / ("%s.%s.obj" % (tag, name))
        with open(obj, "w") as fh:
            for pos in vid:
                fh.write("v %.9g %.9g %.9g\n" % pos)
            for (_, uv) in tid:
                fh.write("vt %.9g %.9g\n" % uv)
            for f in faces:
                fh.write("f %d/%d %d/%d %d/%d\n" % tuple(x + 1 for c in f for x in c))
        out.append((obj, area, len(faces), len(charts) if has_chart else None))
    return out


def atlaseval(obj, res):
    p = subprocess.run([sys.executable, str(TOOLS / "atlaseval.py"), str(obj), str(obj), "--res", "%dx%d" % res],
                       capture_output=True, text=True, timeout=900)
    try:
        return json.loads(p.stdout)
    except ValueError:
        return {"error": (p.stdout + p.stderr).strip()[-300:]}


def score(out_path, sets, group, dims, folder, tag):
    """dims: list of (W, H) per atlas in order, or one (R, R) for all."""
    atlases = write_atlases(out_path, sets, group, folder, tag)
    if len(dims) == 1:
        dims = dims * len(atlases)
    if len(dims) != len(atlases):
        return {"error": "%d atlases in the output, %d sizes logged" % (len(atlases), len(dims))}
    agg = {"atlases": len(atlases), "charts": 0, "chart_attr": 0, "cov": [], "cov_sq": [], "l2w": 0.0, "area": 0.0,
           "flips": 0, "zero_area": 0, "overlap": 0, "cross": 0, "unassigned": 0, "valid": True, "sizes": [], "faces": 0,
           "errors": []}
    for (obj, area, nf, nchart), (W, H) in zip(atlases, dims):
        r = atlaseval(obj, (W, H))
        if "error" in r:
            agg["errors"].append("%s: %s" % (obj.name, r["error"]))
            agg["valid"] = False
            continue
        agg["charts"] += r["charts"]
        agg["chart_attr"] = None if nchart is None or agg["chart_attr"] is None else agg["chart_attr"] + nchart
        agg["cov"].append(r["coverage"])
        agg["cov_sq"].append(r["coverage"] * W * H * r["atlases"] / float(max(W, H) ** 2))
        if r["stretch"]["L2"] is not None:
            agg["l2w"] += r["stretch"]["L2"] ** 2 * area
            agg["area"] += area
        agg["flips"] += r["flipped"]
        agg["zero_area"] += r["zero_area_uv"]
        agg["overlap"] += r["overlap_texels"]
        agg["cross"] += r["boundary_crossings"]["between_charts"] + r["boundary_crossings"]["within_chart"]
        agg["unassigned"] += r["unassigned_faces"]
        agg["valid"] = agg["valid"] and bool(r["valid"])
        agg["sizes"].append((W, H))
        agg["faces"] += nf
    agg["L2"] = math.sqrt(agg["l2w"] / agg["area"]) if agg["area"] > 0 else None
    agg["coverage"] = sum(agg["cov"]) / len(agg["cov"]) if agg["cov"] else None
    agg["coverage_sq"] = sum(agg["cov_sq"]) / len(agg["cov_sq"]) if agg["cov_sq"] else None
    return agg


def read_log(path):
    if not os.path.exists(path):
        return []
    return [json.loads(x) for x in open(path) if x.strip()]


def tag_of(name):
    return name.replace(" ", "").replace("+", "_").replace("(", "").replace(")", "")


def run_tool(row, cmd, env, out, repeat, parse_core):
    """Time cmd (best of repeat; one run when the first takes over 10 s); row gets seconds, runs, core_seconds."""
    best = None
    runs = 0
    for _ in range(repeat):
        dt, p = run_timed(cmd, env)
        if p.returncode != 0 or not out.exists():
            row["error"] = "exit %d: %s" % (p.returncode, (p.stderr or p.stdout).strip().splitlines()[-1][-300:]
                                            if (p.stderr or p.stdout).strip() else "")
            return False
        runs += 1
        if best is None or dt < best[0]:
            best = (dt, p)
        if dt > 10:
            break
    row["seconds"] = best[0]
    row["runs"] = runs
    if parse_core:
        parse_core(row, best[1])
    return True


def harmonia_core(row, p):
    try:
        rep = json.loads(p.stdout)
    except ValueError:
        return
    row["core_seconds"] = sum(x.get("seconds", 0.0) for x in rep.get("atlases", []))
    row["own_report"] = [{k: x.get(k) for k in ("group", "charts", "coverage", "l2_stretch", "flipped_triangles",
                                                "overlapping_texels")} for x in rep.get("atlases", [])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gltf-transform", help="the peer's CLI (else $GLTF_TRANSFORM, else gltf-transform on PATH)")
    ap.add_argument("--harmonia", default=str(SOURCE / "build" / "harmonia"))
    ap.add_argument("--assets", default=str(SHARED / "data" / "gltf"))
    ap.add_argument("--group", choices=["mesh", "primitive"], default="mesh")
    ap.add_argument("--resolution", type=int, default=1024)
    ap.add_argument("--padding", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per tool and asset (best counts); "
                    "one run where the first took over 10 s")
    ap.add_argument("--no-peer-pack", action="store_true", help="leave out the `+pack` row of the peer")
    ap.add_argument("--only", help="comma-separated asset file names")
    ap.add_argument("--keep", help="keep outputs and OBJs in this folder")
    ap.add_argument("--out-md")
    ap.add_argument("--out-json")
    a = ap.parse_args()

    cli = find_peer(a.gltf_transform)
    node = os.environ.get("NODE") or shutil.which("node")
    if not node:
        sys.exit("node is not on PATH\n" + INSTALL)
    if not os.access(a.harmonia, os.X_OK):
        sys.exit("harmonia program not found: %s (build it, or pass --harmonia)" % a.harmonia)
    env = dict(os.environ, PEER_CLI=cli)
    info = json.loads(subprocess.run([node, "-e", PEER_INFO], capture_output=True, text=True, env=env,
                                     check=True).stdout)
    work = pathlib.Path(a.keep) if a.keep else pathlib.Path(tempfile.mkdtemp(prefix="gltf-unwrap-peer-"))
    work.mkdir(parents=True, exist_ok=True)
    hook = work / "watlas_hook.mjs"
    hook.write_text(HOOK)
    prepare = work / "prepare.mjs"
    prepare.write_text(PREPARE)
    hook_env = dict(env, WATLAS_URL=pathlib.Path(info["watlas_path"]).as_uri())

    def prep(mode, src, dst):
        d = subprocess.run([node, str(prepare), mode, str(src), str(dst)], capture_output=True, text=True, env=env)
        if d.returncode != 0:
            raise RuntimeError("%s failed: %s" % (mode, d.stderr.strip()[-300:]))

    assets = sorted(p for p in pathlib.Path(a.assets).iterdir() if p.suffix in (".glb", ".gltf"))
    if a.only:
        keep = set(a.only.split(","))
        assets = [p for p in assets if p.name in keep]
    R = a.resolution
    rows = []
    notes = []
    t_start = time.perf_counter()
    load_start = os.getloadavg()
    for asset in assets:
        j, _ = gltfread.load(str(asset))
        sets, tc, clash = input_texcoord(j)
        nprim = sum(len(m["primitives"]) for m in j.get("meshes", []))
        if clash:
            notes.append("%s: %d primitive(s) already have TEXCOORD_%d; the peer skips them" % (asset.name, clash, tc))
        if len({n for row in sets for n in row}) > 1:
            notes.append("%s: the primitives lack different sets (%s); harmonia writes each primitive's lowest "
                         "missing set, the peer TEXCOORD_%d everywhere (and fills the missing lower sets with it): "
                         "each primitive is scored on its lowest missing set in both" %
                         (asset.name, ", ".join("TEXCOORD_%d" % n for n in sorted({n for r in sets for n in r})), tc))
        stem = asset.stem
        jobs = []
        hout = work / (stem + ".harmonia.glb")
        jobs.append(("harmonia", [a.harmonia, "atlas", str(asset), str(hout), "--resolution", str(R), "--padding",
                                  str(a.padding), "--group", a.group, "--json"], None, hout, harmonia_core))
        peer_inputs = [("", asset)]
        for suffix, src in peer_inputs:
            pout = work / (stem + ".peer%s.glb" % suffix.strip("() ").replace(" ", ""))
            jobs.append(("gltf-transform" + suffix, [cli, "unwrap", str(src), str(pout), "--texcoord", str(tc),
                                                     "--group-by", a.group], None, pout, None))
            if not a.no_peer_pack:
                kout = work / (stem + ".peerpack%s.glb" % suffix.strip("() ").replace(" ", ""))
                jobs.append(("gltf-transform +pack" + suffix,
                             [node, "--import", hook.as_uri(), cli, "unwrap", str(src), str(kout), "--texcoord",
                              str(tc), "--group-by", a.group],
                             dict(hook_env, WATLAS_PACK=json.dumps({"resolution": R, "padding": a.padding})),
                             kout, None))
        k = 0
        while k < len(jobs):
            name, cmd, cenv, out, core = jobs[k]
            k += 1
            row = {"asset": asset.name, "tool": name, "sets": sets, "primitives": nprim,
                   "texcoord": str(tc) if name != "harmonia" else ",".join(str(n) for n in sorted({n for r in sets
                                                                                                    for n in r})),
                   "command": cmd}
            rows.append(row)
            if out.exists():
                out.unlink()
            if not run_tool(row, cmd, cenv, out, a.repeat, core):
                if name == "gltf-transform" and has_strips(j):
                    # the peer cannot take strips: once more on a copy made of triangle lists by its own library
                    tri = work / (stem + ".lists.glb")
                    prep("triangulate", asset, tri)
                    notes.append("%s: the peer fails on the strips (%s); rows marked (lists) ran it on a copy with "
                                 "the strips and fans turned into triangle lists by its own "
                                 "convertPrimitiveToTriangles (not timed)" % (asset.name, row["error"]))
                    extra = []
                    for nm, c, e, o, cr in jobs[k - 1:]:
                        if nm.startswith("gltf-transform"):
                            o2 = o.with_name(o.stem + "_lists.glb")
                            c2 = [o2.as_posix() if x == str(o) else (str(tri) if x == str(asset) else x) for x in c]
                            extra.append((nm + " (lists)", c2, e, o2, cr))
                    jobs.extend(extra)
                continue
            if name.startswith("gltf-transform"):
                log = work / (stem + "." + tag_of(name) + ".log.jsonl")
                if log.exists():
                    log.unlink()
                if cenv is None:
                    # once more, untimed, under the hook that only logs; the file must be the same
                    lout = out.with_name(out.stem + "_logged.glb")
                    lcmd = [node, "--import", hook.as_uri()] + [lout.as_posix() if x == str(out) else x for x in cmd]
                    subprocess.run(lcmd, capture_output=True, env=dict(hook_env, WATLAS_LOG=str(log)), timeout=600)
                    if not lout.exists() or lout.read_bytes() != out.read_bytes():
                        notes.append("%s: the peer's logged run wrote a different file than its timed run" %
                                     asset.name)
                else:
                    subprocess.run(cmd, capture_output=True, env=dict(cenv, WATLAS_LOG=str(log)), timeout=600)
                recs = read_log(log)
                dims = [(r["width"], r["height"]) for r in recs]
                row["core_seconds"] = sum(r["ms"] for r in recs) / 1000.0
                row["xatlas"] = recs
                if any(r["atlasCount"] != 1 for r in recs):
                    notes.append("%s %s: xatlas packed into %s atlases, the UVs of which gltf-transform puts in one"
                                 % (asset.name, name, [r["atlasCount"] for r in recs]))
            else:
                dims = [(R, R)]
            oj, _ = gltfread.load(str(out))
            src = out
            row["output_compressed"] = is_compressed(oj)
            try:
                if row["output_compressed"]:
                    src = out.with_name(out.stem + "_decoded.glb")
                    prep("decompress", out, src)
                row["score"] = score(src, sets, a.group, dims, work, stem + "." + tag_of(name))
            except Exception as e:  # noqa: BLE001 - reported in the row
                row["error"] = "scoring: %s: %s" % (type(e).__name__, e)
        if is_compressed(j):
            notes.append("%s: the input is compressed (%s); %s" % (
                asset.name, ", ".join(x for x in j.get("extensionsUsed", []) if "compression" in x),
                "; ".join("%s writes it %s" % (r["tool"], "compressed" if r["output_compressed"] else "uncompressed")
                          for r in rows if r["asset"] == asset.name and "output_compressed" in r)))
        print("%s done (%.0f s so far)" % (asset.name, time.perf_counter() - t_start), file=sys.stderr)

    info["load"] = (load_start, os.getloadavg(), os.cpu_count())
    md = render(rows, notes, info, a, cli)
    print(md)
    if a.out_md:
        pathlib.Path(a.out_md).write_text(md)
    if a.out_json:
        pathlib.Path(a.out_json).write_text(json.dumps({"peer": info, "rows": rows, "notes": notes}, indent=1,
                                                       default=str))
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)


def fmt(x, spec):
    return "" if x is None else format(x, spec)


def render(rows, notes, info, a, cli):
    out = []
    out.append("glTF-Transform `unwrap` (CLI %s, @gltf-transform/functions %s, watlas %s = xatlas in WebAssembly, "
               "node %s) beside `harmonia atlas` (--resolution %d --padding %d), grouping `%s` for both, "
               "%d timed run(s) each (best). Scored by gltfread.py + atlaseval.py on every atlas of the outputs."
               % (info["cli"], info["functions"], info["watlas"], info["node"], a.resolution, a.padding, a.group,
                  a.repeat))
    out.append("")
    (l0, l1, ncpu) = info["load"]
    out.append("Load average (1, 5, 15 min) at the start %s, at the end %s, on %d CPUs; harmonia `%s`, peer `%s`."
               % ("/".join("%.2f" % x for x in l0), "/".join("%.2f" % x for x in l1), ncpu, a.harmonia, cli))
    out.append("")
    out.append("| asset | tool | TEXCOORD | atlases | charts | atlas size | coverage | cov. sq | L2 stretch | flips (0-area) "
               "| overlap texels | crossings | valid | time s | core s |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "error" in r and "score" not in r:
            out.append("| %s | %s | %s | | | | | | | | | | error: %s | %s | |" % (
                r["asset"], r["tool"], r["texcoord"], r["error"].replace("|", "/").replace("\n", " "),
                fmt(r.get("seconds"), ".2f")))
            continue
        s = r["score"]
        if "error" in s:
            out.append("| %s | %s | %s | | | | | | | | | | error: %s | %.2f | |" % (
                r["asset"], r["tool"], r["texcoord"], s["error"], r["seconds"]))
            continue
        sizes = sorted(set(s["sizes"]))
        size = ", ".join("%dx%d" % wh for wh in sizes[:3]) + (" ..." if len(sizes) > 3 else "")
        valid = "yes" if s["valid"] else "NO"
        if s["errors"]:
            valid += " (%d atlaseval errors)" % len(s["errors"])
        if s["unassigned"]:
            valid += " (%d faces unassigned)" % s["unassigned"]
        out.append("| %s | %s | %s | %d | %d | %s | %s | %s | %s | %s | %d | %d | %s | %.2f | %s |" % (
            r["asset"], r["tool"], r["texcoord"], s["atlases"], s["charts"], size, fmt(s["coverage"], ".3f"),
            fmt(s["coverage_sq"], ".3f"), fmt(s["L2"], ".4f"),
            "%d (%d)" % (s["flips"], s["zero_area"]) if s["zero_area"] else str(s["flips"]), s["overlap"], s["cross"], valid,
            r["seconds"], fmt(r.get("core_seconds"), ".3f")))
    out.append("")
    for r in rows:
        s = r.get("score") or {}
        own = r.get("own_report")
        if own and "charts" in s and sum(x["charts"] or 0 for x in own) != s["charts"]:
            notes.append("%s harmonia: its report counts %d charts, atlaseval %d" % (
                r["asset"], sum(x["charts"] or 0 for x in own), s["charts"]))
        if r["tool"] == "harmonia" and s.get("chart_attr") not in (None, s.get("charts")):
            notes.append("%s harmonia: atlaseval counts %d charts (shared-vt components), its _CHART attribute %d"
                         % (r["asset"], s["charts"], s["chart_attr"]))
        if r.get("output_compressed"):
            notes.append("%s %s: the output is under EXT_meshopt_compression; decoded with the peer's "
                         "@gltf-transform/core + meshoptimizer for scoring" % (r["asset"], r["tool"]))
        for e in s.get("errors", []):
            notes.append("%s %s: atlaseval: %s" % (r["asset"], r["tool"], e))
    if notes:
        out.append("Notes:")
        out.append("")
        out.extend("- " + n for n in dict.fromkeys(notes))
        out.append("")
    return "\n".join(out)


if __name__ == "__main__":
    main()
