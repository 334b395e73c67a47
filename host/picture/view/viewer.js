/*
 * viewer.js: the browser side of `harmonia view`.
 *
 * Reads the result data, JSON in the page's script element with the id
 * "harmonia-data", and shows, for every result, two linked views side by side: the 3D model
 * (three.js with OrbitControls; the 3D views of all results share one camera)
 * and its UV square. The triangle under the mouse, and more lightly its chart,
 * is highlighted in both views and described in a hover box.
 *
 * Needs the global THREE (three.js r111) and THREE.OrbitControls. Plain ES2017,
 * no modules. It never touches the network.
 *
 * Test hooks, kept stable for the Selenium test (all on window.harmoniaView):
 *   ready                         true once every view has drawn its first frame
 *   error                         null, or the message shown when the page could not start
 *   setMode(key)                  colour by "checker" or by a field key; redraws;
 *                                 returns false for an unknown key
 *   mode()                        the current colour mode key
 *   faceCentreOnScreen(resultIndex, face, view)
 *                                 view "3d" or "uv": {x, y} client (viewport) coordinates
 *                                 of the triangle's centroid in that canvas (3D: projected
 *                                 with the current camera), or null when off screen,
 *                                 behind the camera, or not shown
 *   pickAt(resultIndex, view, clientX, clientY)
 *                                 index of the face under that client point, or -1
 *   hoverText()                   the hover box's text, "" when none; one "label: value"
 *                                 per line after the result's name, e.g. "chart: 2"
 *   colourBar(resultIndex = 0)    {low, high, ticks: [labels as shown]} of the current
 *                                 mode for that result; null for checker or when the
 *                                 result has no such field
 */
(function () {
  'use strict';

  // Until the viewer runs (or when it cannot), the hooks answer "nothing there".
  const hooks = {
    ready: false,
    error: null,
    setMode: () => false,
    mode: () => 'checker',
    faceCentreOnScreen: () => null,
    pickAt: () => -1,
    hoverText: () => '',
    colourBar: () => null,
  };
  window.harmoniaView = hooks;

  // ─── Appearance ───────────────────────────────────────────────────────────

  const CHECKER_LIGHT = '#f3f0e8';
  const CHECKER_DARK = '#7d8fa5';
  const CHECKER_TILES = 10;            // texture repeats across [0,1]; each tile holds 2 x 2 checks
  const BACKGROUND_3D = 0xeef0f3;
  const BACKGROUND_UV = 0xd9dde3;
  const UV_SQUARE = 0xffffff;
  const UV_FRAME = 0x737a84;
  const BOUNDARY_COLOUR = 0x14202e;
  const FLIPPED_COLOUR = 0xff00cc;
  const HIGHLIGHT_FILL = 0xffa000;
  const HIGHLIGHT_EDGE = 0x000000;
  const CHART_TINT = 0xffed73;           // mixed into the hovered chart
  const UNDEFINED_GREY = [150, 150, 150];
  const NO_CHART = -1.0e9;               // hover uniform value that matches no chart id

  // Colour maps as evenly spaced stops: a viridis-like ramp for magnitudes,
  // blue–white–red around zero for signed quantities.
  const SEQUENTIAL_STOPS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  const DIVERGING_STOPS = [[59, 76, 192], [141, 176, 254], [242, 242, 242], [244, 154, 123], [180, 4, 38]];

  const UV_FIT = 0.56;                 // half the visible height at zoom 1: the unit square plus a margin
  const CHUNK_FACES = 1024;            // faces per box for 3D picking

  // ─── Reading the data ─────────────────────────────────────────────────────

  // A problem the page reports in words (bad data, no WebGL) rather than as an exception.
  class ViewerError extends Error {}

  function readData() {
    const element = document.getElementById('harmonia-data');
    if (!element) throw new ViewerError('the page holds no data');
    try {
      return JSON.parse(element.textContent);
    } catch (error) {
      throw new ViewerError('the data is not valid JSON (' + error.message + ')');
    }
  }

  function bytesFromBase64(text, what) {
    let binary;
    try {
      binary = atob(text || '');
    } catch (error) {
      throw new ViewerError(what + ' is not valid base64');
    }
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return bytes;
  }

  // The wire format is little-endian, as are typed arrays on every platform a
  // browser runs on, so the decoded bytes are used in place.
  function decodeArray(text, Type, count, what) {
    const bytes = bytesFromBase64(text, what);
    const expected = count * Type.BYTES_PER_ELEMENT;
    if (bytes.length !== expected) {
      throw new ViewerError(what + ': expected ' + expected + ' bytes, found ' + bytes.length);
    }
    return new Type(bytes.buffer);
  }

  function checkIndices(indices, limit, what) {
    for (let i = 0; i < indices.length; i++) {
      if (indices[i] >= limit) throw new ViewerError(what + ': index ' + indices[i] + ' out of range');
    }
  }

  function readCount(value, what) {
    const n = Number(value || 0);
    if (!Number.isInteger(n) || n < 0) throw new ViewerError(what + ' is not a count');
    return n;
  }

  function labelPairs(pairs) {
    if (!Array.isArray(pairs)) return [];
    return pairs
      .filter(pair => Array.isArray(pair) && pair.length >= 2)
      .map(pair => [String(pair[0]), String(pair[1])]);
  }

  // ─── Numbers and colours ──────────────────────────────────────────────────

  // At most `digits` significant digits, without trailing zeros.
  function formatSignificant(x, digits) {
    if (!Number.isFinite(x)) return Number.isNaN(x) ? 'n/a' : String(x);
    if (x === 0) return '0';
    const parts = x.toPrecision(digits).split('e');
    const mantissa = parts[0].includes('.') ? parts[0].replace(/\.?0+$/, '') : parts[0];
    return parts.length === 2 ? mantissa + 'e' + parts[1] : mantissa;
  }

  const formatTick = x => formatSignificant(x, 4);
  const formatValue = x => formatSignificant(x, 6);

  // A tick between the ends is a round number: it gets at least 4 digits and
  // as many more as it takes to write it exactly, so that close ticks differ.
  function formatInnerTick(x) {
    for (let digits = 4; digits < 15; digits++) {
      if (Number(x.toPrecision(digits)) === Number(x.toPrecision(15))) return formatSignificant(x, digits);
    }
    return formatSignificant(x, 15);
  }

  function tickLabels(values) {
    return values.map((x, i) => (i === 0 || i === values.length - 1 ? formatTick(x) : formatInnerTick(x)));
  }

  // Colour bar ticks: both ends as given, and between them one to three round
  // values that keep clear of the ends.
  function tickValues(low, high) {
    const span = high - low;
    if (!(span > 0) || !Number.isFinite(span)) return [low, high];
    const margin = 0.12 * span;
    const magnitude = Math.pow(10, Math.floor(Math.log10(span)));
    let oneTick = null;
    for (const factor of [5, 2.5, 2, 1, 0.5, 0.25, 0.2, 0.1]) {
      const step = factor * magnitude;
      const inner = [];
      for (let k = Math.ceil((low + margin) / step); k * step <= high - margin; k++) inner.push(k * step);
      if (inner.length >= 2 && inner.length <= 3) return [low].concat(inner, [high]);
      if (inner.length === 1 && !oneTick) oneTick = [low, inner[0], high];
    }
    return oneTick || [low, (low + high) / 2, high];
  }

  function sampleStops(stops, t) {
    const x = Math.min(Math.max(t, 0), 1) * (stops.length - 1);
    const i = Math.min(Math.floor(x), stops.length - 2);
    const f = x - i;
    return stops[i].map((c, k) => Math.round(c + (stops[i + 1][k] - c) * f));
  }

  // 256 RGB colours, so that painting a million faces is a table look-up each.
  function lookupTable(stops) {
    const table = new Uint8Array(256 * 3);
    for (let i = 0; i < 256; i++) table.set(sampleStops(stops, i / 255), 3 * i);
    return table;
  }

  const SEQUENTIAL_TABLE = lookupTable(SEQUENTIAL_STOPS);
  const DIVERGING_TABLE = lookupTable(DIVERGING_STOPS);

  const cssColour = rgb => 'rgb(' + rgb.join(',') + ')';

  // ─── Per-face fields ──────────────────────────────────────────────────────

  class Field {
    constructor(raw, faceCount) {
      this.key = String(raw.key || raw.name);
      this.name = String(raw.name || raw.key);
      this.unit = raw.unit ? String(raw.unit) : '';
      this.low = Number(raw.low);
      this.high = Number(raw.high);
      this.symmetric = raw.symmetric === true;
      this.values = decodeArray(raw.values, Float32Array, faceCount, 'field "' + this.key + '"');
      this.ticks = tickLabels(tickValues(this.low, this.high));
    }

    stops() {
      return this.symmetric ? DIVERGING_STOPS : SEQUENTIAL_STOPS;
    }

    // Where a value sits on the colour bar: 0 at low, 1 at high, NaN for
    // undefined. A symmetric field puts 0 at the middle whatever low and high are.
    barPosition(value) {
      if (Number.isNaN(value)) return NaN;
      const low = this.low, high = this.high;
      let t;
      if (this.symmetric && low < 0 && high > 0) {
        t = value < 0 ? 0.5 * (1 - value / low) : 0.5 + 0.5 * value / high;
      } else {
        t = high > low ? (value - low) / (high - low) : 0.5;
      }
      return Math.min(Math.max(t, 0), 1);
    }
  }

  // ─── Mesh helpers ─────────────────────────────────────────────────────────

  // Copies per-vertex values to every face corner (non-indexed layout), so
  // per-face colours and UV seams come out exact.
  function gatherCorners(values, indices, width) {
    const out = new Float32Array(indices.length * width);
    for (let corner = 0; corner < indices.length; corner++) {
      const from = indices[corner] * width;
      for (let k = 0; k < width; k++) out[corner * width + k] = values[from + k];
    }
    return out;
  }

  function spreadToCorners(perFace) {
    const out = new Float32Array(3 * perFace.length);
    for (let face = 0; face < perFace.length; face++) out.fill(perFace[face], 3 * face, 3 * face + 3);
    return out;
  }

  // Bounding box of the finite points of a flat coordinate array, or null.
  function finiteBounds(values, width) {
    const min = new Array(width).fill(Infinity);
    const max = new Array(width).fill(-Infinity);
    for (let i = 0; i < values.length; i += width) {
      let finite = true;
      for (let k = 0; k < width; k++) finite = finite && Number.isFinite(values[i + k]);
      if (!finite) continue;
      for (let k = 0; k < width; k++) {
        min[k] = Math.min(min[k], values[i + k]);
        max[k] = Math.max(max[k], values[i + k]);
      }
    }
    return min[0] <= max[0] ? { min: min, max: max } : null;
  }

  const nextCorner = corner => corner - corner % 3 + (corner % 3 + 1) % 3;

  // Segments (6 floats each, z 0 for 2D corners) from each half-edge's corner to the next corner,
  // the corners `stride` floats apart in `corners`.
  function cornerSegments(corners, stride, halfEdges) {
    const out = new Float32Array(6 * halfEdges.length);
    halfEdges.forEach((h, i) => {
      out.set(corners.subarray(stride * h, stride * h + stride), 6 * i);
      out.set(corners.subarray(stride * nextCorner(h), stride * nextCorner(h) + stride), 6 * i + 3);
    });
    return out;
  }

  // Do two half-edges of one 3D edge use the same uv vertices?
  function sameUvEdge(faces, uvFaces, h, g) {
    const uvStart = uvFaces[h], uvEnd = uvFaces[nextCorner(h)];
    if (faces[g] === faces[h]) return uvFaces[g] === uvStart && uvFaces[nextCorner(g)] === uvEnd;
    return uvFaces[nextCorner(g)] === uvStart && uvFaces[g] === uvEnd;
  }

  // Chart boundaries as half-edges (named by their first corner): edges with
  // faces of different charts, UV seams (same 3D edge, other uv vertices),
  // edges with one face and non-manifold edges. `edges` has one half-edge per
  // 3D edge, `sides` every half-edge, since a seam shows twice in the UV square.
  function findChartBoundaries(faces, uvFaces, chart, vertexCount) {
    const cornerCount = faces.length;
    const lowEnd = h => Math.min(faces[h], faces[nextCorner(h)]);
    const highEnd = h => Math.max(faces[h], faces[nextCorner(h)]);
    const faceOf = h => (h / 3) | 0;
    const isBoundary = (h, g) =>
      chart[faceOf(h)] !== chart[faceOf(g)] || (uvFaces !== null && !sameUvEdge(faces, uvFaces, h, g));

    // Bucket the half-edges by their lower vertex (a counting sort).
    const bucketStart = new Uint32Array(vertexCount + 1);
    for (let h = 0; h < cornerCount; h++) bucketStart[lowEnd(h) + 1]++;
    for (let v = 0; v < vertexCount; v++) bucketStart[v + 1] += bucketStart[v];
    const cursor = bucketStart.slice(0, vertexCount);
    const bucket = new Uint32Array(cornerCount);
    for (let h = 0; h < cornerCount; h++) bucket[cursor[lowEnd(h)]++] = h;

    const edges = new Uint32Array(cornerCount);
    const sides = new Uint32Array(cornerCount);
    let edgeCount = 0, sideCount = 0;
    for (let v = 0; v < vertexCount; v++) {
      // Within a bucket, half-edges with the same higher vertex are one 3D edge.
      const group = bucket.subarray(bucketStart[v], bucketStart[v + 1]);
      if (group.length > 1) group.sort((p, q) => highEnd(p) - highEnd(q));
      for (let i = 0, j; i < group.length; i = j) {
        const high = highEnd(group[i]);
        for (j = i + 1; j < group.length && highEnd(group[j]) === high; j++);
        if (high === v) continue;  // degenerate: from a vertex to itself
        if (j - i === 2 && !isBoundary(group[i], group[i + 1])) continue;
        edges[edgeCount++] = group[i];
        for (let k = i; k < j; k++) sides[sideCount++] = group[k];
      }
    }
    return { edges: edges.slice(0, edgeCount), sides: sides.slice(0, sideCount) };
  }

  // ─── Picking structures ───────────────────────────────────────────────────

  function triangleContains(uvs, face, u, v) {
    const k = 6 * face;
    const ax = uvs[k], ay = uvs[k + 1], bx = uvs[k + 2], by = uvs[k + 3], cx = uvs[k + 4], cy = uvs[k + 5];
    const d1 = (bx - ax) * (v - ay) - (by - ay) * (u - ax);
    const d2 = (cx - bx) * (v - by) - (cy - by) * (u - bx);
    const d3 = (ax - cx) * (v - cy) - (ay - cy) * (u - cx);
    const negative = d1 < 0 || d2 < 0 || d3 < 0;
    const positive = d1 > 0 || d2 > 0 || d3 > 0;
    return !(negative && positive);  // either winding: flipped faces count too
  }

  // A uniform grid over the UV layout; each cell lists the faces whose
  // bounding box touches it, so a point query tests only a few triangles.
  class UvGrid {
    constructor(cornerUvs, faceCount) {
      this.uvs = cornerUvs;
      this.cells = 0;
      const bounds = finiteBounds(cornerUvs, 2);
      if (!bounds || faceCount === 0) return;
      this.origin = bounds.min;
      this.extent = [Math.max(bounds.max[0] - bounds.min[0], 1e-12), Math.max(bounds.max[1] - bounds.min[1], 1e-12)];
      // About one face per cell; coarser when large triangles would fill too many cells.
      let cells = Math.min(1024, Math.ceil(Math.sqrt(faceCount)));
      while (cells > 1 && this.entryCount(cells, faceCount) > 8 * faceCount + 4096) cells = Math.ceil(cells / 2);
      this.fill(cells, faceCount);
    }

    cellOf(x, axis, cells) {
      const i = Math.floor((x - this.origin[axis]) / this.extent[axis] * cells);
      return Math.min(cells - 1, Math.max(0, i));
    }

    // Writes the face's cell range i0, i1, j0, j1 into `range`; false when its uvs are undefined.
    cellRange(face, cells, range) {
      const k = 6 * face, uvs = this.uvs;
      const u0 = uvs[k], u1 = uvs[k + 2], u2 = uvs[k + 4], v0 = uvs[k + 1], v1 = uvs[k + 3], v2 = uvs[k + 5];
      if (!Number.isFinite(u0 + u1 + u2 + v0 + v1 + v2)) return false;
      range[0] = this.cellOf(Math.min(u0, u1, u2), 0, cells);
      range[1] = this.cellOf(Math.max(u0, u1, u2), 0, cells);
      range[2] = this.cellOf(Math.min(v0, v1, v2), 1, cells);
      range[3] = this.cellOf(Math.max(v0, v1, v2), 1, cells);
      return true;
    }

    entryCount(cells, faceCount) {
      const r = new Int32Array(4);
      let total = 0;
      for (let face = 0; face < faceCount; face++) {
        if (this.cellRange(face, cells, r)) total += (r[1] - r[0] + 1) * (r[3] - r[2] + 1);
      }
      return total;
    }

    // Two passes over the faces: count per cell, then list (compressed rows).
    fill(cells, faceCount) {
      const r = new Int32Array(4);
      const forEachCell = visit => {
        for (let face = 0; face < faceCount; face++) {
          if (!this.cellRange(face, cells, r)) continue;
          for (let j = r[2]; j <= r[3]; j++) for (let i = r[0]; i <= r[1]; i++) visit(j * cells + i, face);
        }
      };
      const start = new Uint32Array(cells * cells + 1);
      forEachCell(cell => { start[cell + 1]++; });
      for (let c = 0; c < cells * cells; c++) start[c + 1] += start[c];
      const cursor = start.slice(0, cells * cells);
      const faces = new Uint32Array(start[cells * cells]);
      forEachCell((cell, face) => { faces[cursor[cell]++] = face; });
      this.cells = cells;
      this.start = start;
      this.faces = faces;
    }

    // Faces whose triangle holds (u, v).
    facesAt(u, v) {
      const found = [];
      if (this.cells === 0) return found;
      const inside = (x, axis) => x >= this.origin[axis] && x <= this.origin[axis] + this.extent[axis];
      if (!inside(u, 0) || !inside(v, 1)) return found;
      const cell = this.cellOf(v, 1, this.cells) * this.cells + this.cellOf(u, 0, this.cells);
      for (let k = this.start[cell]; k < this.start[cell + 1]; k++) {
        if (triangleContains(this.uvs, this.faces[k], u, v)) found.push(this.faces[k]);
      }
      return found;
    }
  }

  // Runs of consecutive faces boxed together: a ray tests the boxes first and
  // then only the triangles of the boxes it passes, nearest box first.
  class FaceChunks {
    constructor(cornerPositions, faceCount) {
      this.corners = cornerPositions;
      this.chunks = [];
      const point = new THREE.Vector3();
      for (let first = 0; first < faceCount; first += CHUNK_FACES) {
        const last = Math.min(first + CHUNK_FACES, faceCount);
        const box = new THREE.Box3();
        for (let i = 9 * first; i < 9 * last; i += 3) {
          point.fromArray(cornerPositions, i);
          if (Number.isFinite(point.x + point.y + point.z)) box.expandByPoint(point);
        }
        if (!box.isEmpty()) this.chunks.push({ box: box, first: first, last: last });
      }
    }

    nearestFace(ray) {
      const entry = new THREE.Vector3(), hit = new THREE.Vector3();
      const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
      const candidates = [];
      for (const chunk of this.chunks) {
        if (ray.intersectBox(chunk.box, entry)) candidates.push({ chunk: chunk, distance: entry.distanceTo(ray.origin) });
      }
      candidates.sort((p, q) => p.distance - q.distance);
      let nearest = -1, nearestDistance = Infinity;
      for (const candidate of candidates) {
        if (candidate.distance > nearestDistance) break;
        for (let face = candidate.chunk.first; face < candidate.chunk.last; face++) {
          a.fromArray(this.corners, 9 * face);
          b.fromArray(this.corners, 9 * face + 3);
          c.fromArray(this.corners, 9 * face + 6);
          if (!ray.intersectTriangle(a, b, c, false, hit)) continue;
          const distance = hit.distanceTo(ray.origin);
          if (distance < nearestDistance) {
            nearestDistance = distance;
            nearest = face;
          }
        }
      }
      return nearest;
    }
  }

  // ─── One result, decoded ──────────────────────────────────────────────────

  class ResultModel {
    constructor(raw, index) {
      this.index = index;
      this.name = String(raw.name || 'result ' + (index + 1));
      this.method = String(raw.method || '');
      this.kind = String(raw.kind || 'uv');
      this.figures = labelPairs(raw.figures);
      const faceCount = readCount(raw.face_count, 'face_count');
      const vertexCount = readCount(raw.vertex_count, 'vertex_count');
      const uvCount = readCount(raw.uv_count, 'uv_count');
      this.faceCount = faceCount;

      const positions = decodeArray(raw.positions, Float32Array, 3 * vertexCount, 'positions');
      const faces = decodeArray(raw.faces, Uint32Array, 3 * faceCount, 'faces');
      checkIndices(faces, vertexCount, 'faces');
      this.hasUv = typeof raw.uv_faces === 'string' && (faceCount === 0 || raw.uv_faces.length > 0);
      let uvFaces = null;
      if (this.hasUv) {
        const uvs = decodeArray(raw.uvs, Float32Array, 2 * uvCount, 'uvs');
        uvFaces = decodeArray(raw.uv_faces, Uint32Array, 3 * faceCount, 'uv_faces');
        checkIndices(uvFaces, uvCount, 'uv_faces');
        this.cornerUvs = gatherCorners(uvs, uvFaces, 2);
      } else {
        this.cornerUvs = new Float32Array(6 * faceCount);
      }
      this.chart = decodeArray(raw.chart, Int32Array, faceCount, 'chart');
      this.flipped = raw.flipped ? decodeArray(raw.flipped, Uint8Array, faceCount, 'flipped') : new Uint8Array(faceCount);
      this.fields = (Array.isArray(raw.fields) ? raw.fields : []).map(field => new Field(field, faceCount));
      this.charts = new Map();
      (Array.isArray(raw.charts) ? raw.charts : []).forEach(info => this.charts.set(Number(info.id), info));

      this.bounds = finiteBounds(positions, 3);
      this.cornerPositions = gatherCorners(positions, faces, 3);
      this.cornerCharts = spreadToCorners(this.chart);
      this.cornerColours = new Uint8Array(9 * faceCount);
      this.cornerFlipped = new Uint8Array(3 * faceCount);  // 255 (1.0 in the shader) at flipped faces' corners
      this.flippedFaces = [];
      this.flipped.forEach((isFlipped, face) => {
        if (!isFlipped) return;
        this.cornerFlipped.fill(255, 3 * face, 3 * face + 3);
        this.flippedFaces.push(face);
      });
      this.boundary = findChartBoundaries(faces, uvFaces, this.chart, vertexCount);
      this.grid = null;       // built on the first UV pick
      this.chunks = null;     // built on the first 3D pick
    }

    field(key) {
      return this.fields.find(field => field.key === key) || null;
    }

    chartInfo(id) {
      const info = Object.assign({}, this.charts.get(id));
      if (typeof info.faces !== 'number') info.faces = this.chart.reduce((n, c) => n + (c === id ? 1 : 0), 0);
      return info;
    }

    // Triangles of the listed faces as 9 floats each, in 3D or in the UV plane (z = 0).
    triangles3d(faces) {
      const out = new Float32Array(9 * faces.length);
      faces.forEach((face, i) => out.set(this.cornerPositions.subarray(9 * face, 9 * face + 9), 9 * i));
      return out;
    }

    trianglesUv(faces) {
      const out = new Float32Array(9 * faces.length);
      faces.forEach((face, i) => {
        for (let k = 0; k < 3; k++) out.set(this.cornerUvs.subarray(6 * face + 2 * k, 6 * face + 2 * k + 2), 9 * i + 3 * k);
      });
      return out;
    }

    // Line segments (6 floats each) from each half-edge's corner to the next corner.
    segments3d(halfEdges) {
      return cornerSegments(this.cornerPositions, 3, halfEdges);
    }

    segmentsUv(halfEdges) {
      return cornerSegments(this.cornerUvs, 2, halfEdges);
    }

    centroid3d(face) {
      const p = this.cornerPositions, k = 9 * face;
      const mean = i => (p[k + i] + p[k + 3 + i] + p[k + 6 + i]) / 3;
      return new THREE.Vector3(mean(0), mean(1), mean(2));
    }

    centroidUv(face) {
      const t = this.cornerUvs, k = 6 * face;
      return { u: (t[k] + t[k + 2] + t[k + 4]) / 3, v: (t[k + 1] + t[k + 3] + t[k + 5]) / 3 };
    }

    // Writes every corner's colour from the field, grey where it is undefined
    // (or when the field is missing altogether).
    paint(field) {
      const colours = this.cornerColours;
      const table = field && field.symmetric ? DIVERGING_TABLE : SEQUENTIAL_TABLE;
      const grey = new Uint8Array(UNDEFINED_GREY);
      for (let face = 0; face < this.faceCount; face++) {
        const t = field ? field.barPosition(field.values[face]) : NaN;
        const source = Number.isNaN(t) ? grey : table;
        const at = Number.isNaN(t) ? 0 : 3 * Math.round(255 * t);
        for (let k = 9 * face; k < 9 * face + 9; k += 3) {
          colours[k] = source[at];
          colours[k + 1] = source[at + 1];
          colours[k + 2] = source[at + 2];
        }
      }
    }

    // The face drawn on top at (u, v): flipped faces are drawn over the rest,
    // otherwise later faces over earlier ones.
    faceAtUv(u, v) {
      if (!this.grid) this.grid = new UvGrid(this.cornerUvs, this.faceCount);
      const rank = face => (this.flipped[face] ? this.faceCount : 0) + face;
      return this.grid.facesAt(u, v).reduce((best, face) => (best < 0 || rank(face) > rank(best) ? face : best), -1);
    }

    faceAlongRay(ray) {
      if (!this.chunks) this.chunks = new FaceChunks(this.cornerPositions, this.faceCount);
      return this.chunks.nearestFace(ray);
    }
  }

  // ─── three.js pieces ──────────────────────────────────────────────────────

  function webglAvailable() {
    const canvas = document.createElement('canvas');
    const gl = canvas.getContext('webgl') || canvas.getContext('experimental-webgl');
    if (!gl) return false;
    const loser = gl.getExtension('WEBGL_lose_context');
    if (loser) loser.loseContext();  // give the context slot back
    return true;
  }

  function makeCheckerTexture() {
    const size = 256, half = size / 2;
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = size;
    const g = canvas.getContext('2d');
    g.fillStyle = CHECKER_LIGHT;
    g.fillRect(0, 0, size, size);
    g.fillStyle = CHECKER_DARK;
    g.fillRect(0, 0, half, half);
    g.fillRect(half, half, half, half);
    const texture = new THREE.CanvasTexture(canvas);
    texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
    texture.anisotropy = 8;  // three clamps this to what the GPU offers
    return texture;
  }

  // What the surface's vertex shader hands its fragment shader.
  const SURFACE_VARYINGS = [
    'varying vec3 vColour;',
    'varying vec2 vUv;',
    'varying float vHovered;',
    'varying float vFlipped;',
    'varying vec3 vViewPosition;',
  ];

  const SURFACE_VERTEX_SHADER = [
    'attribute vec3 faceColour;',
    'attribute float chart;',
    'attribute float flipped;',
    'uniform float hoverChart;',
    ...SURFACE_VARYINGS,
    'void main() {',
    '#ifdef UV_VIEW',
    '  vUv = position.xy;',  // in the UV view the position is the uv pair
    '#else',
    '  vUv = uv;',
    '#endif',
    '  vColour = faceColour;',
    '  vHovered = abs(chart - hoverChart) < 0.5 ? 1.0 : 0.0;',
    '  vFlipped = flipped;',
    '  vec4 viewPosition = modelViewMatrix * vec4(position, 1.0);',
    '  vViewPosition = viewPosition.xyz;',
    '  gl_Position = projectionMatrix * viewPosition;',
    '}',
  ].join('\n');

  const SURFACE_FRAGMENT_SHADER = [
    'uniform sampler2D checker;',
    'uniform float checkerTiles;',
    'uniform vec2 checkerOrigin;',
    'uniform float checkerSize;',
    'uniform bool useChecker;',
    'uniform vec3 chartTint;',
    'uniform bool showFlipped;',
    'uniform vec3 flippedColour;',
    ...SURFACE_VARYINGS,
    'void main() {',
    '  if (showFlipped && vFlipped > 0.5) {',  // solid, unshaded: it must stand out
    '    gl_FragColor = vec4(flippedColour, 1.0);',
    '    return;',
    '  }',
    '  vec2 checkerUv = (vUv - checkerOrigin) / checkerSize * checkerTiles;',
    '  vec3 colour = useChecker ? texture2D(checker, checkerUv).rgb : vColour;',
    '  colour = mix(colour, chartTint, 0.4 * vHovered);',
    '#ifdef SHADED',
    // Flat shading from screen-space derivatives: the face normal without storing normals.
    '  vec3 normal = normalize(cross(dFdx(vViewPosition), dFdy(vViewPosition)));',
    '  float facing = abs(dot(normal, normalize(-vViewPosition)));',
    '  colour *= 0.45 + 0.55 * facing;',
    '#endif',
    '  gl_FragColor = vec4(colour, 1.0);',
    '}',
  ].join('\n');

  function hasDerivatives(renderer) {
    const extensions = renderer.getContext().getSupportedExtensions() || [];
    return renderer.capabilities.isWebGL2 || extensions.indexOf('OES_standard_derivatives') >= 0;
  }

  // Pushes a material's triangles back in depth (forward when negative), by slope and by units.
  function offsetDepth(material, amount) {
    Object.assign(material, { polygonOffset: true, polygonOffsetFactor: amount, polygonOffsetUnits: amount });
  }

  // square: the UV square the result's views frame (squareAroundUvs); the checker covers it.
  function makeSurfaceMaterial(checker, square, inUvView, shaded) {
    const defines = {};
    if (inUvView) defines.UV_VIEW = 1;
    if (shaded) defines.SHADED = 1;
    const material = new THREE.ShaderMaterial({
      uniforms: {
        checker: { value: checker },
        checkerTiles: { value: CHECKER_TILES },
        checkerOrigin: { value: new THREE.Vector2(square.u, square.v) },
        checkerSize: { value: square.size },
        useChecker: { value: true },
        hoverChart: { value: NO_CHART },
        chartTint: { value: new THREE.Color(CHART_TINT) },
        showFlipped: { value: true },
        flippedColour: { value: new THREE.Color(FLIPPED_COLOUR) },
      },
      vertexShader: SURFACE_VERTEX_SHADER,
      fragmentShader: SURFACE_FRAGMENT_SHADER,
      defines: defines,
      extensions: { derivatives: shaded },
      side: THREE.DoubleSide,
      depthTest: !inUvView,
      depthWrite: !inUvView,
    });
    // In 3D the surface is pushed back so that its edges and the highlight win the depth test.
    if (!inUvView) offsetDepth(material, 1);
    return material;
  }

  // Without depth, objects are drawn in painter's order (renderOrder): all of the UV view is.
  function depthOptions(useDepth, extra) {
    return Object.assign({ depthTest: useDepth, depthWrite: useDepth }, extra);
  }

  function geometryOf(attributes) {
    const geometry = new THREE.BufferGeometry();
    Object.keys(attributes).forEach(name => geometry.setAttribute(name, attributes[name]));
    return geometry;
  }

  function makeTriangles(positions, colour, useDepth, renderOrder) {
    const geometry = geometryOf({ position: new THREE.BufferAttribute(positions, 3) });
    const material = new THREE.MeshBasicMaterial(depthOptions(useDepth, { color: colour, side: THREE.DoubleSide }));
    const mesh = new THREE.Mesh(geometry, material);
    mesh.renderOrder = renderOrder;
    mesh.frustumCulled = false;
    return mesh;
  }

  function makeLines(Kind, positions, colour, useDepth, renderOrder) {
    const geometry = geometryOf({ position: new THREE.BufferAttribute(positions, 3) });
    const lines = new Kind(geometry, new THREE.LineBasicMaterial(depthOptions(useDepth, { color: colour })));
    lines.renderOrder = renderOrder;
    lines.frustumCulled = false;
    return lines;
  }

  // The hovered triangle: a filled triangle with an outline, moved by
  // rewriting 9 floats, so hovering never rebuilds the big geometry.
  class FaceHighlight {
    constructor(scene, inUvView) {
      this.fill = makeTriangles(new Float32Array(9), HIGHLIGHT_FILL, !inUvView, 5);
      if (!inUvView) offsetDepth(this.fill.material, -1);
      // The outline is drawn last and without depth: the hovered face is in front anyway.
      this.outline = makeLines(THREE.LineLoop, new Float32Array(9), HIGHLIGHT_EDGE, false, 6);
      [this.fill, this.outline].forEach(object => {
        object.visible = false;
        scene.add(object);
      });
    }

    show(triangle) {
      [this.fill, this.outline].forEach(object => {
        const position = object.geometry.getAttribute('position');
        position.array.set(triangle);
        position.needsUpdate = true;
        object.visible = true;
      });
    }

    hide() {
      this.fill.visible = this.outline.visible = false;
    }
  }

  // ─── Views ────────────────────────────────────────────────────────────────

  // A canvas with its own WebGL renderer, sized to its panel, drawn on demand.
  class CanvasView {
    constructor(viewer, row, panel, background) {
      this.viewer = viewer;
      this.row = row;
      this.panel = panel;
      this.canvas = document.createElement('canvas');
      panel.appendChild(this.canvas);
      this.renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: true, preserveDrawingBuffer: true });
      this.renderer.setPixelRatio(window.devicePixelRatio || 1);
      this.renderer.setClearColor(background, 1);
      this.scene = new THREE.Scene();
      this.width = 0;
      this.height = 0;
      this.dirty = true;
      this.drawn = false;
      this.fitToPanel();
      this.canvas.addEventListener('pointermove', event => viewer.pointerMoved(this, event));
      this.canvas.addEventListener('pointerleave', () => viewer.pointerLeft(this));
    }

    fitToPanel() {
      const width = Math.max(1, this.panel.clientWidth), height = Math.max(1, this.panel.clientHeight);
      if (width === this.width && height === this.height) return;
      this.width = width;
      this.height = height;
      this.renderer.setSize(width, height, false);  // CSS keeps the canvas filling its panel
    }

    draw() {
      this.fitToPanel();
      this.updateCamera();
      this.renderer.render(this.scene, this.camera);
      this.drawn = true;
    }

    // Normalized device coordinates of a client point, or null outside the canvas.
    ndcAt(clientX, clientY) {
      const rect = this.canvas.getBoundingClientRect();
      const x = (clientX - rect.left) / rect.width, y = (clientY - rect.top) / rect.height;
      if (!(x >= 0 && x <= 1 && y >= 0 && y <= 1)) return null;
      return new THREE.Vector2(2 * x - 1, 1 - 2 * y);
    }

    clientAt(ndcX, ndcY) {
      if (!(Math.abs(ndcX) <= 1 && Math.abs(ndcY) <= 1)) return null;
      const rect = this.canvas.getBoundingClientRect();
      return { x: rect.left + (ndcX + 1) / 2 * rect.width, y: rect.top + (1 - ndcY) / 2 * rect.height };
    }
  }

  // The 3D model; its camera is shared with the other results' 3D views.
  class ModelView extends CanvasView {
    constructor(viewer, row, panel, orbit) {
      super(viewer, row, panel, BACKGROUND_3D);
      const model = row.model;
      this.camera = orbit.camera;
      this.material = makeSurfaceMaterial(viewer.checker, squareAroundUvs(model.cornerUvs), false,
                                          hasDerivatives(this.renderer));
      const surface = new THREE.Mesh(geometryOf({
        position: new THREE.BufferAttribute(model.cornerPositions, 3),
        uv: new THREE.BufferAttribute(model.cornerUvs, 2),
        faceColour: row.colourAttribute,
        chart: row.chartAttribute,
        flipped: row.flippedAttribute,  // the surface shader paints flipped faces itself
      }), this.material);
      surface.frustumCulled = false;  // no bounding sphere to compute, and undefined positions do no harm
      this.boundaryLines = makeLines(THREE.LineSegments, model.segments3d(model.boundary.edges), BOUNDARY_COLOUR, true, 2);
      this.scene.add(surface, this.boundaryLines);
      this.highlight = new FaceHighlight(this.scene, false);
      this.raycaster = new THREE.Raycaster();
      orbit.attach(this.canvas);
    }

    updateCamera() {
      this.camera.aspect = this.width / this.height;
      this.camera.zoom = Math.min(1, this.camera.aspect);  // a tall view still shows the model's width
      this.camera.updateProjectionMatrix();
      this.camera.updateMatrixWorld();
    }

    pick(clientX, clientY) {
      const ndc = this.ndcAt(clientX, clientY);
      if (!ndc) return -1;
      this.updateCamera();
      this.raycaster.setFromCamera(ndc, this.camera);
      return this.row.model.faceAlongRay(this.raycaster.ray);
    }

    faceCentre(face) {
      this.updateCamera();
      const centre = this.row.model.centroid3d(face);
      const inCameraSpace = centre.clone().applyMatrix4(this.camera.matrixWorldInverse);
      if (!(inCameraSpace.z < -this.camera.near)) return null;  // behind the camera
      centre.project(this.camera);
      return this.clientAt(centre.x, centre.y);
    }

    showFace(face) {
      if (face < 0) this.highlight.hide();
      else this.highlight.show(this.row.model.triangles3d([face]));
    }
  }

  // The square a UV view frames: the unit square of an atlas (UVs within [0, 1]), else the
  // smallest square around the layout (a flattening's UVs keep its own units and place).
  function squareAroundUvs(uvs) {
    let uMin = Infinity, vMin = Infinity, uMax = -Infinity, vMax = -Infinity;
    for (let i = 0; i + 1 < uvs.length; i += 2) {
      const u = uvs[i], v = uvs[i + 1];
      if (!Number.isFinite(u) || !Number.isFinite(v)) continue;
      if (u < uMin) uMin = u;
      if (u > uMax) uMax = u;
      if (v < vMin) vMin = v;
      if (v > vMax) vMax = v;
    }
    const slack = 1e-6;
    const inUnitSquare = !(uMin < -slack || vMin < -slack || uMax > 1 + slack || vMax > 1 + slack);
    let square = { u: 0, v: 0, size: 1 };
    if (!inUnitSquare && uMax >= uMin) {
      const size = Math.max(uMax - uMin, vMax - vMin) || 1;
      square = { u: (uMin + uMax - size) / 2, v: (vMin + vMax - size) / 2, size: size };
    }
    square.centre = function () { return { u: this.u + this.size / 2, v: this.v + this.size / 2 }; };
    return square;
  }

  // The UV square: an orthographic view of the plane, panned by dragging and
  // zoomed with the wheel about the cursor; double-click resets it.
  class UvView extends CanvasView {
    constructor(viewer, row, panel) {
      super(viewer, row, panel, BACKGROUND_UV);
      const model = row.model;
      this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.1, 10);
      this.camera.position.set(0, 0, 1);
      this.square = squareAroundUvs(model.cornerUvs);
      this.centre = this.square.centre();
      this.zoom = 1;
      this.material = makeSurfaceMaterial(viewer.checker, this.square, true, false);
      // The uv pairs serve as positions directly: WebGL reads the missing z as 0.
      const surface = new THREE.Mesh(geometryOf({
        position: new THREE.BufferAttribute(model.cornerUvs, 2),
        faceColour: row.colourAttribute,
        chart: row.chartAttribute,
        flipped: row.flippedAttribute,
      }), this.material);
      surface.frustumCulled = false;  // three's bounding sphere would assume 3 coordinates
      surface.renderOrder = 1;
      const s = this.square;
      const u0 = s.u, v0 = s.v, u1 = s.u + s.size, v1 = s.v + s.size;
      const square = makeTriangles(new Float32Array([u0, v0, 0, u1, v0, 0, u1, v1, 0, u0, v0, 0, u1, v1, 0, u0, v1, 0]), UV_SQUARE, false, 0);
      const frame = makeLines(THREE.LineLoop, new Float32Array([u0, v0, 0, u1, v0, 0, u1, v1, 0, u0, v1, 0]), UV_FRAME, false, 4);
      // Flipped faces overlap their neighbours: drawn again, over everything else.
      this.flippedMesh = makeTriangles(model.trianglesUv(model.flippedFaces), FLIPPED_COLOUR, false, 2);
      this.boundaryLines = makeLines(THREE.LineSegments, model.segmentsUv(model.boundary.sides), BOUNDARY_COLOUR, false, 3);
      this.scene.add(square, surface, this.flippedMesh, this.boundaryLines, frame);
      this.highlight = new FaceHighlight(this.scene, true);
      this.listenForPanAndZoom();
    }

    // Half the visible width and height in uv units: the framed square fits at zoom 1.
    halfExtents() {
      const aspect = this.width / this.height;
      const halfHeight = this.square.size * Math.max(UV_FIT, UV_FIT / aspect) / this.zoom;
      return { u: halfHeight * aspect, v: halfHeight };
    }

    updateCamera() {
      const half = this.halfExtents(), camera = this.camera;
      camera.left = this.centre.u - half.u;
      camera.right = this.centre.u + half.u;
      camera.bottom = this.centre.v - half.v;
      camera.top = this.centre.v + half.v;
      camera.updateProjectionMatrix();
    }

    uvAt(clientX, clientY) {
      const ndc = this.ndcAt(clientX, clientY);
      if (!ndc) return null;
      const half = this.halfExtents();
      return { u: this.centre.u + ndc.x * half.u, v: this.centre.v + ndc.y * half.v };
    }

    pick(clientX, clientY) {
      const point = this.uvAt(clientX, clientY);
      return point ? this.row.model.faceAtUv(point.u, point.v) : -1;
    }

    faceCentre(face) {
      const centre = this.row.model.centroidUv(face), half = this.halfExtents();
      return this.clientAt((centre.u - this.centre.u) / half.u, (centre.v - this.centre.v) / half.v);
    }

    showFace(face) {
      if (face < 0) this.highlight.hide();
      else this.highlight.show(this.row.model.trianglesUv([face]));
    }

    resetView() {
      this.centre = this.square.centre();
      this.zoom = 1;
      this.viewer.requestDraw(this);
    }

    zoomAbout(clientX, clientY, factor) {
      const anchor = this.uvAt(clientX, clientY);
      const zoom = Math.min(Math.max(this.zoom * factor, 0.2), 1e5);
      if (!anchor || zoom === this.zoom) return;
      const scale = this.zoom / zoom;  // keeps the point under the cursor in place
      this.centre = { u: anchor.u + (this.centre.u - anchor.u) * scale, v: anchor.v + (this.centre.v - anchor.v) * scale };
      this.zoom = zoom;
      this.viewer.requestDraw(this);
    }

    panByPixels(dx, dy) {
      const half = this.halfExtents();
      this.centre = { u: this.centre.u - 2 * half.u * dx / this.width, v: this.centre.v + 2 * half.v * dy / this.height };
      this.viewer.requestDraw(this);
    }

    listenForPanAndZoom() {
      const canvas = this.canvas;
      let drag = null;
      canvas.addEventListener('wheel', event => {
        event.preventDefault();
        const pixels = event.deltaY * (event.deltaMode === 1 ? 16 : 1);
        this.zoomAbout(event.clientX, event.clientY, Math.exp(-0.0015 * pixels));
      }, { passive: false });
      canvas.addEventListener('pointerdown', event => {
        if (event.button !== 0) return;
        drag = { x: event.clientX, y: event.clientY };
        canvas.setPointerCapture(event.pointerId);
      });
      canvas.addEventListener('pointermove', event => {
        if (!drag) return;
        this.panByPixels(event.clientX - drag.x, event.clientY - drag.y);
        drag = { x: event.clientX, y: event.clientY };
      });
      const endDrag = () => { drag = null; };
      canvas.addEventListener('pointerup', endDrag);
      canvas.addEventListener('pointercancel', endDrag);
      canvas.addEventListener('dblclick', () => this.resetView());
    }
  }

  // One perspective camera and one orbit target for all 3D views, each view
  // with its own OrbitControls: turning one view turns them all.
  class SharedOrbit {
    constructor(bounds, onChange) {
      const min = bounds ? new THREE.Vector3().fromArray(bounds.min) : new THREE.Vector3(-1, -1, -1);
      const max = bounds ? new THREE.Vector3().fromArray(bounds.max) : new THREE.Vector3(1, 1, 1);
      const radius = Math.max(min.distanceTo(max) / 2, 1e-6);
      const fov = 35;
      const distance = 1.15 * radius / Math.sin(fov / 2 * Math.PI / 180);  // the bounding sphere fills the view
      this.radius = radius;
      this.homeTarget = min.clone().add(max).multiplyScalar(0.5);
      this.homePosition = new THREE.Vector3(0.9, 0.7, 1.4).normalize().multiplyScalar(distance).add(this.homeTarget);
      this.camera = new THREE.PerspectiveCamera(fov, 1, 0.01 * radius, 100 * radius);
      this.target = this.homeTarget.clone();
      this.onChange = onChange;
      this.controls = [];
      this.camera.position.copy(this.homePosition);
      this.camera.lookAt(this.target);
    }

    attach(canvas) {
      const controls = new THREE.OrbitControls(this.camera, canvas);
      controls.target = this.target;  // the same vector in every controls object
      controls.screenSpacePanning = true;
      controls.minDistance = 0.05 * this.radius;
      controls.maxDistance = 40 * this.radius;
      controls.update();
      controls.addEventListener('change', this.onChange);
      this.controls.push(controls);
    }

    reset() {
      this.target.copy(this.homeTarget);
      this.camera.position.copy(this.homePosition);
      this.controls.forEach(controls => controls.update());
      this.onChange();
    }
  }

  // ─── Page parts ───────────────────────────────────────────────────────────

  function element(tag, className, text) {
    const node = document.createElement(tag);
    if (className) node.className = className;
    if (text !== undefined) node.textContent = text;
    return node;
  }

  // Fills a <dl> with label/value pairs.
  function fillPairList(list, pairs) {
    pairs.forEach(pair => {
      const item = element('div', 'pair');
      item.append(element('dt', '', pair[0]), element('dd', '', pair[1]));
      list.appendChild(item);
    });
    return list;
  }

  const pairList = (className, pairs) => fillPairList(element('dl', className), pairs);

  class ColourBar {
    constructor(container) {
      this.container = container;
      this.state = null;
    }

    show(field) {
      this.container.textContent = '';
      this.container.hidden = false;
      this.state = { low: field.low, high: field.high, ticks: field.ticks.slice() };
      const title = element('div', 'colour-bar-title', field.name + (field.unit ? ' (' + field.unit + ')' : ''));
      const ramp = element('div', 'colour-bar-ramp');
      const samples = [];
      for (let i = 0; i <= 32; i++) {
        const value = field.low + (field.high - field.low) * i / 32;
        samples.push(cssColour(sampleStops(field.stops(), field.barPosition(value))));
      }
      ramp.style.background = 'linear-gradient(to right, ' + samples.join(', ') + ')';
      const ticks = element('div', 'colour-bar-ticks');
      const values = tickValues(field.low, field.high);
      field.ticks.forEach((label, i) => {
        const tick = element('span', 'tick', label);
        const at = field.high > field.low ? (values[i] - field.low) / (field.high - field.low) : i / (values.length - 1);
        tick.style.left = (100 * at).toFixed(3) + '%';
        if (i === 0) tick.classList.add('first');
        if (i === values.length - 1) tick.classList.add('last');
        ticks.appendChild(tick);
      });
      this.container.append(title, ramp, ticks);
    }

    showMissing(key) {
      this.state = null;
      this.container.hidden = false;
      this.container.textContent = '';
      this.container.appendChild(element('div', 'colour-bar-missing', 'no "' + key + '" in this result'));
    }

    hide() {
      this.state = null;
      this.container.hidden = true;
      this.container.textContent = '';
    }
  }

  class HoverBox {
    constructor(box) {
      this.box = box;
      this.lines = [];
    }

    show(title, pairs) {
      this.lines = [title].concat(pairs.map(pair => pair[0] + ': ' + pair[1]));
      this.box.textContent = '';
      this.box.appendChild(element('div', 'hover-title', title));
      const table = element('table');
      pairs.forEach(pair => {
        const row = element('tr');
        row.append(element('th', '', pair[0]), element('td', '', pair[1]));
        table.appendChild(row);
      });
      this.box.appendChild(table);
      this.box.hidden = false;
    }

    moveTo(clientX, clientY) {
      const gap = 16, box = this.box;
      const x = Math.min(clientX + gap, window.innerWidth - box.offsetWidth - 4);
      const y = clientY + gap + box.offsetHeight > window.innerHeight ? clientY - gap - box.offsetHeight : clientY + gap;
      box.style.left = Math.max(4, x) + 'px';
      box.style.top = Math.max(4, y) + 'px';
    }

    hide() {
      this.lines = [];
      this.box.hidden = true;
    }

    text() {
      return this.lines.join('\n');
    }
  }

  function describeFace(model, face) {
    const chartId = model.chart[face];
    const info = model.chartInfo(chartId);
    const pairs = [
      ['face', String(face)],
      ['chart', String(chartId)],
      ['faces in chart', String(info.faces)],
      ['chart L2 stretch', typeof info.l2_stretch === 'number' ? formatValue(info.l2_stretch) : 'n/a'],
    ];
    model.fields.forEach(field => {
      const value = field.values[face];
      pairs.push([field.name, formatValue(value) + (field.unit && !Number.isNaN(value) ? ' ' + field.unit : '')]);
    });
    if (model.flipped[face]) pairs.push(['flipped', 'yes']);
    pairs.push(['method', model.method || 'n/a']);
    return { title: model.name, pairs: pairs };
  }

  // One result: its header (name, figures, colour bar) and its two views.
  class ResultRow {
    constructor(viewer, container, model, problem) {
      this.model = model;
      this.modelView = null;
      this.uvView = null;
      const section = element('section', 'result');
      const header = element('header', 'result-header');
      const name = model ? model.name : problem.name;
      header.appendChild(element('h2', '', name));
      if (model && model.method) header.appendChild(element('span', 'method', model.method));
      if (model) header.appendChild(pairList('figures', model.figures));
      this.colourBar = new ColourBar(element('div', 'colour-bar'));
      header.appendChild(this.colourBar.container);
      const views = element('div', 'result-views');
      const panel3d = this.panel('view-3d', '3D');
      const panelUv = this.panel('view-uv', 'UV');
      views.append(panel3d, panelUv);
      section.append(header, views);
      container.appendChild(section);

      if (!model) {
        const message = 'cannot show this result: ' + problem.message;
        [panel3d, panelUv].forEach(panel => this.message(panel, message));
      } else if (model.faceCount === 0) {
        [panel3d, panelUv].forEach(panel => this.message(panel, 'no faces'));
      } else {
        this.colourAttribute = new THREE.BufferAttribute(model.cornerColours, 3, true);
        this.chartAttribute = new THREE.BufferAttribute(model.cornerCharts, 1);
        this.flippedAttribute = new THREE.BufferAttribute(model.cornerFlipped, 1, true);
        this.modelView = new ModelView(viewer, this, panel3d, viewer.orbit);
        if (model.hasUv) this.uvView = new UvView(viewer, this, panelUv);
        else this.message(panelUv, 'no UV layout (kind "' + model.kind + '")');
      }
    }

    panel(className, label) {
      const panel = element('div', 'view ' + className);
      panel.appendChild(element('span', 'view-label', label));
      return panel;
    }

    message(panel, text) {
      panel.appendChild(element('div', 'view-message', text));
    }

    views() {
      return [this.modelView, this.uvView].filter(Boolean);
    }

    view(name) {
      return name === 'uv' ? this.uvView : name === '3d' ? this.modelView : null;
    }

    applyMode(key) {
      if (!this.model) return;
      const useChecker = key === 'checker';
      if (useChecker) {
        this.colourBar.hide();
      } else {
        const field = this.model.field(key);
        this.model.paint(field);
        if (this.colourAttribute) this.colourAttribute.needsUpdate = true;
        if (field) this.colourBar.show(field);
        else this.colourBar.showMissing(key);
      }
      this.views().forEach(view => { view.material.uniforms.useChecker.value = useChecker; });
    }

    showHover(face) {
      const chart = face >= 0 ? this.model.chart[face] : NO_CHART;
      this.views().forEach(view => {
        view.material.uniforms.hoverChart.value = chart;
        view.showFace(face);
      });
    }

    showBoundaries(visible) {
      this.views().forEach(view => { view.boundaryLines.visible = visible; });
    }

    showFlipped(visible) {
      this.views().forEach(view => {
        view.material.uniforms.showFlipped.value = visible;
        if (view.flippedMesh) view.flippedMesh.visible = visible;
      });
    }
  }

  // ─── The viewer ───────────────────────────────────────────────────────────

  class Viewer {
    constructor(data) {
      this.hover = null;          // {row, face, view}
      this.pendingPick = null;    // the latest pointer position still to be picked
      this.frameRequested = false;
      this.fillTitle(data);
      this.checker = makeCheckerTexture();
      const results = Array.isArray(data.results) ? data.results : [];
      const decoded = results.map((raw, index) => this.decode(raw, index));
      const models = decoded.filter(entry => entry.model).map(entry => entry.model);
      this.orbit = new SharedOrbit(unionBounds(models), () => this.requestDraw3d());
      const container = document.getElementById('results');
      if (results.length === 0) container.appendChild(element('div', 'page-message', 'no results'));
      this.rows = decoded.map(entry => new ResultRow(this, container, entry.model, entry.problem));
      this.views = [].concat.apply([], this.rows.map(row => row.views()));
      this.hoverBox = new HoverBox(document.getElementById('hover-box'));
      this.modes = this.collectModes(models);
      this.mode = 'checker';
      this.wireToolbar();
      this.setMode('checker');
      this.watchSizes();
      this.requestFrame();
    }

    decode(raw, index) {
      try {
        const model = new ResultModel(raw, index);
        // Drop the base64 text now decoded, so it can be garbage collected.
        ['positions', 'faces', 'uvs', 'uv_faces', 'chart', 'flipped'].forEach(key => { raw[key] = null; });
        (raw.fields || []).forEach(field => { field.values = null; });
        return { model: model };
      } catch (error) {
        if (!(error instanceof ViewerError)) throw error;
        return { model: null, problem: { name: String(raw && raw.name || 'result ' + (index + 1)), message: error.message } };
      }
    }

    fillTitle(data) {
      document.getElementById('title').textContent = String(data.title || '');
      fillPairList(document.getElementById('headline'), labelPairs(data.headline));
    }

    // "checker" and every field key of any result, named as the first result that has it names it.
    collectModes(models) {
      const modes = [{ key: 'checker', name: 'checker' }];
      models.forEach(model => model.fields.forEach(field => {
        if (!modes.some(mode => mode.key === field.key)) modes.push({ key: field.key, name: field.name });
      }));
      return modes;
    }

    wireToolbar() {
      const select = document.getElementById('colour-mode');
      this.modes.forEach(mode => {
        const option = element('option', '', mode.name);
        option.value = mode.key;
        select.appendChild(option);
      });
      select.addEventListener('change', () => this.setMode(select.value));
      this.modeSelect = select;
      const toggle = (id, show) => {
        const box = document.getElementById(id);
        box.addEventListener('change', () => {
          this.rows.forEach(row => show(row, box.checked));
          this.requestDrawAll();
        });
      };
      toggle('show-boundaries', (row, visible) => row.showBoundaries(visible));
      toggle('show-flipped', (row, visible) => row.showFlipped(visible));
      document.getElementById('reset-views').addEventListener('click', () => {
        this.orbit.reset();
        this.rows.forEach(row => { if (row.uvView) row.uvView.resetView(); });
      });
    }

    setMode(key) {
      if (!this.modes.some(mode => mode.key === key)) return false;
      this.mode = key;
      this.modeSelect.value = key;
      this.rows.forEach(row => row.applyMode(key));
      this.requestDrawAll();
      return true;
    }

    watchSizes() {
      const redraw = () => this.requestDrawAll();
      if (typeof ResizeObserver === 'function') {
        const observer = new ResizeObserver(redraw);
        this.views.forEach(view => observer.observe(view.panel));
      } else {
        window.addEventListener('resize', redraw);
      }
    }

    // ── drawing on demand: at most one frame per display refresh ──

    requestFrame() {
      if (this.frameRequested) return;
      this.frameRequested = true;
      requestAnimationFrame(() => this.frame());
    }

    requestDraw(view) {
      view.dirty = true;
      this.requestFrame();
    }

    requestDraw3d() {
      this.rows.forEach(row => { if (row.modelView) this.requestDraw(row.modelView); });
    }

    requestDrawAll() {
      this.views.forEach(view => this.requestDraw(view));
      this.requestFrame();
    }

    frame() {
      this.frameRequested = false;
      if (this.pendingPick) {
        const pick = this.pendingPick;
        this.pendingPick = null;
        const face = pick.view.pick(pick.x, pick.y);
        this.setHover(face >= 0 ? { row: pick.view.row, face: face, view: pick.view } : null, pick.x, pick.y);
      }
      this.views.forEach(view => {
        if (!view.dirty) return;
        view.dirty = false;
        view.draw();
      });
      if (!hooks.ready && this.views.every(view => view.drawn)) hooks.ready = true;
    }

    // ── hover ──

    pointerMoved(view, event) {
      if (event.buttons !== 0) {  // turning, panning: no hover meanwhile
        this.pendingPick = null;
        this.setHover(null);
        return;
      }
      this.pendingPick = { view: view, x: event.clientX, y: event.clientY };
      this.requestFrame();
    }

    pointerLeft(view) {
      if (this.pendingPick && this.pendingPick.view === view) this.pendingPick = null;
      if (this.hover && this.hover.view === view) this.setHover(null);
    }

    setHover(hover, clientX, clientY) {
      const previous = this.hover;
      const unchanged = previous && hover && previous.row === hover.row && previous.face === hover.face;
      this.hover = hover;
      if (!unchanged) {
        if (previous) this.redrawRow(previous.row, -1);
        if (hover) this.redrawRow(hover.row, hover.face);
        if (hover) {
          const description = describeFace(hover.row.model, hover.face);
          this.hoverBox.show(description.title, description.pairs);
        } else {
          this.hoverBox.hide();
        }
      }
      if (hover) this.hoverBox.moveTo(clientX, clientY);
    }

    redrawRow(row, face) {
      row.showHover(face);
      row.views().forEach(view => this.requestDraw(view));
    }
  }

  function unionBounds(models) {
    const boxes = models.map(model => model.bounds).filter(Boolean);
    if (boxes.length === 0) return null;
    return {
      min: [0, 1, 2].map(k => Math.min.apply(null, boxes.map(box => box.min[k]))),
      max: [0, 1, 2].map(k => Math.max.apply(null, boxes.map(box => box.max[k]))),
    };
  }

  // ─── Start ────────────────────────────────────────────────────────────────

  function installHooks(viewer) {
    const rowAt = index => viewer.rows[index] || null;
    const faceIn = (row, face) => row && row.model && Number.isInteger(face) && face >= 0 && face < row.model.faceCount;
    hooks.setMode = key => viewer.setMode(key);
    hooks.mode = () => viewer.mode;
    hooks.faceCentreOnScreen = (resultIndex, face, view) => {
      const row = rowAt(resultIndex);
      const target = row && row.view(view);
      return target && faceIn(row, face) ? target.faceCentre(face) : null;
    };
    hooks.pickAt = (resultIndex, view, clientX, clientY) => {
      const row = rowAt(resultIndex);
      const target = row && row.view(view);
      return target ? target.pick(clientX, clientY) : -1;
    };
    hooks.hoverText = () => viewer.hoverBox.text();
    hooks.colourBar = resultIndex => {
      const row = rowAt(resultIndex === undefined ? 0 : resultIndex);
      const state = row && viewer.mode !== 'checker' ? row.colourBar.state : null;
      return state ? { low: state.low, high: state.high, ticks: state.ticks.slice() } : null;
    };
  }

  function showFailure(message) {
    hooks.error = message;
    const container = document.getElementById('results');
    if (container) container.appendChild(element('div', 'page-message', message));
  }

  function start() {
    try {
      if (typeof THREE === 'undefined' || !THREE.OrbitControls) throw new ViewerError('three.js is missing from the page');
      const data = readData();
      if (!webglAvailable()) throw new ViewerError('this browser cannot draw WebGL');
      installHooks(new Viewer(data));
    } catch (error) {
      if (!(error instanceof ViewerError)) throw error;
      showFailure(error.message);
    }
  }

  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
  else start();
})();
