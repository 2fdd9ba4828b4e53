// gradmesh mesh script: draws SVG 2 <meshgradient> fills in browsers that implement none.
//
// Every SVG gradmesh writes with meshes ends with this script, minified (docs/browsers.md). For
// each shape painted with a meshgradient (fill="url(#id)" or style="fill:url(#id) ...") it
// tessellates the mesh's patches into small triangles with per-vertex colour, draws them at the
// device resolution of the shape's on-screen box (its own rasteriser, into a 2D canvas), and
// paints the shape with the result as an <image> in a <pattern>: the browser's own path
// anti-aliasing still gives the outline.
//
// Geometry and colour follow the SVG 2 mesh definition as gradmesh reads it
// (formats/svg/src/svg_reader.cpp) and renders it (meshcore/src/render*.cpp):
//  - each patch is a bicubic tensor-product Bézier patch: its edges from the stops' paths, its
//    interior points from the `tensor` attribute, else the Coons interior points;
//  - type="bicubic": the colour is the bicubic Hermite interpolant of the corner colours with
//    zero twists, whose slope at a corner along a patch edge is g·L: g from the SVG 2 bicubic
//    rule along the meshgradient's row or column line through the corner (limited mean of the
//    neighbouring secants, parabolic at the ends; meshcore/src/bicubic_colors.cpp), L the chord
//    of the patch edge; any other type: bilinear in the patch parameters.
//
// Runs once per page however many SVGs carry it: the first copy defines window.gradmeshMeshes
// ({redraw(), scan(), mode}); later copies only ask it to scan for shapes not drawn yet.
// window.gradmeshMeshOptions, when set before, may ask for {timing: true} (the draw time on the
// console).
(() => {
  if (window.SVGMeshGradientElement) return;  // native meshes
  if (window.gradmeshMeshes) return window.gradmeshMeshes.scan();

  const {abs, ceil, floor, hypot, max, min, sqrt} = Math;
  const SVG_NS = 'http://www.w3.org/2000/svg', F64 = Float64Array;
  const create = (name, ns = 'http://www.w3.org/1999/xhtml') => document.createElementNS(ns, name);
  // Largest canvas side and area drawn (device pixels; what browsers' canvases take in
  // practice); larger boxes are drawn coarser.
  const MAX_SIDE = 4096, MAX_AREA = 1 << 24;
  // Subdivision: position error (device px) and colour error (0–1) of the linear triangles,
  // the smallest cell (device px) the colour alone asks for, and the most cells per side.
  const POSITION_TOLERANCE = 0.2, COLOUR_TOLERANCE = 0.6 / 255, SMALLEST_CELL = 1.5;
  const MAX_CELLS = 64;
  // Half the width (device px) of the skirt around each patch: a strip along its border,
  // drawn before the patches, so that pixels on a mesh's border whose centre no triangle
  // covers are not transparent inside the anti-aliased path, nor those whose centre falls
  // between two differently subdivided patches. Pixels further out stay transparent: holes
  // and the seam bands' ends there show nothing.
  const SKIRT = 0.75;

  const options = window.gradmeshMeshOptions || {};
  const records = [];  // one per painted shape: {meshShape, gradient, mesh, tile, tileImage, key}
  let patternCount = 0;

  // ---- Parsing ---------------------------------------------------------------------------

  const numbers = (text) => (text.match(/[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/g) || []).map(Number);
  // The value of the attribute `name` in the markup of an element's attributes, or ''.
  const patterns = {};
  const attribute = (markup, name) =>
    ((patterns[name] ||= RegExp(`\\s${name}="([^"]*)`)).exec(markup) || [, ''])[1];

  // The meshgradient id a shape's fill names.
  const paintedId = (shape) =>
    (/url\(\s*['"]?[^#)]*#([^)'"\s]+)/.exec(shape.style.fill || shape.getAttribute('fill')) || [])[1];

  // The element with `id`, looked up in the shape's outermost <svg> first: a page that inlines
  // several gradmesh SVGs repeats their ids.
  function elementById(el, id) {
    let root = el;
    while (root.ownerSVGElement) root = root.ownerSVGElement;
    return root.querySelector(`[id="${id}"]`) || document.getElementById(id);
  }

  // An sRGB colour 0–1 from a stop's attributes (markup; the style's stop-color first): #rgb or
  // #rrggbb, else whatever the browser makes of the stop, the index-th one in `source`.
  function stopColour(stop, index, source) {
    const text = (/stop-color:\s*([^;"]*)/.exec(stop) || [])[1] || attribute(stop, 'stop-color') || '#000';
    const hex = (/^\s*#([0-9a-f]{3}|[0-9a-f]{6})\b/i.exec(text) || [])[1];
    const rgb = hex ? null : numbers(getComputedStyle(source.getElementsByTagName('stop')[index]).stopColor);
    return [0, 1, 2].map((k) => (rgb ? rgb[k] :
      parseInt(hex.length > 3 ? hex.substr(2 * k, 2) : hex[k] + hex[k], 16)) / 255);
  }

  // Affine transforms [a b c d e f] (x' = a x + c y + e, y' = b x + d y + f).
  const multiply = (m, t) => [m[0] * t[0] + m[2] * t[1], m[1] * t[0] + m[3] * t[1],
    m[0] * t[2] + m[2] * t[3], m[1] * t[2] + m[3] * t[3],
    m[0] * t[4] + m[2] * t[5] + m[4], m[1] * t[4] + m[3] * t[5] + m[5]];  // first t, then m

  // A gradientTransform: matrix, translate and scale (what editors write).
  function parseTransform(text) {
    let m = [1, 0, 0, 1, 0, 0];
    for (const [, name, args] of (text || '').matchAll(/(\w+)\s*\(([^)]*)\)/g)) {
      const v = numbers(args);
      m = multiply(m, name == 'matrix' ? v : name == 'translate' ? [1, 0, 0, 1, v[0], v[1] || 0] :
        name == 'scale' ? [v[0], 0, 0, v[1] ?? v[0], 0, 0] : [1, 0, 0, 1, 0, 0]);
    }
    return m;
  }

  const lerp = (p, q, f) => [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])];

  // One stop's edge from `start` (its attributes' markup): [handle 1, handle 2, end]. A closing
  // edge ends at the corner `end` already known, and may leave its end point out.
  function parseEdge(stop, start, end) {
    const path = attribute(stop, 'path').trim(), v = numbers(path), c = path[0], r = c == 'c' || c == 'l';
    const point = (k) => [v[2 * k] + (r && start[0]), v[2 * k + 1] + (r && start[1])];
    if (c == 'c' || c == 'C') return [point(0), point(1), v.length > 4 ? point(2) : end];
    if (v.length) end = point(0);
    return [lerp(start, end, 1 / 3), lerp(start, end, 2 / 3), end];
  }

  // The rows of the meshgradient `source`, read from its markup (serialised by the browser at
  // once: far faster than visiting each element): per row its patches, per patch the markup of
  // its attributes, then per stop the markup of its attributes and its index in `source`.
  function meshRows(source) {
    const rows = [];
    let patch = [], index = 0;
    for (const [, name, attributes] of source.outerHTML.matchAll(/<(meshrow|meshpatch|stop)\b([^>]*)/g))
      name == 'stop' ? patch.push([attributes, index++]) :
        name == 'meshrow' ? rows.push([]) : rows.at(-1)?.push(patch = [attributes]);
    return rows;
  }

  // The meshgradient (its href chain included) as a grid of C×R patches: corners P and their
  // colours, horizontal edge handles H (left corner first), vertical V (top first), tensor
  // points per patch.
  function parseMesh(gradient) {
    const chain = [gradient];
    for (let g = gradient; (g = hrefTarget(g)) && !chain.includes(g);) chain.push(g);
    const attr = (name) => (chain.find((g) => g.hasAttribute(name)) || gradient).getAttribute(name);
    const source = chain.find((g) => g.querySelector('meshrow')) || gradient, rows = meshRows(source);
    const R = rows.length, C = R && rows[0].length, W = C + 1;
    const P = [[+attr('x') || 0, +attr('y') || 0]], H = [], V = [], colour = [], tensor = [];
    rows.forEach((row, r) => row.slice(0, C).forEach((patch, c) => {
      const stops = patch.slice(1), tl = r * W + c, bl = tl + W;  // corner indices
      const next = (start, end, corner) => {  // the next stop: its edge and its start's colour
        const [stop, index] = stops.shift();
        if (corner >= 0) colour[corner] = stopColour(stop, index, source);
        return parseEdge(stop, P[start], P[end]);
      };
      let e;
      if (!r) {  // top, left to right
        H[c] = e = next(c, -1, c ? -1 : 0);
        P[c + 1] = e[2];
      }
      e = next(tl + 1, -1, r ? -1 : c + 1);  // right, top to bottom
      V[tl + 1] = e;
      P[bl + 1] = e[2];
      e = next(bl + 1, bl, bl + 1);  // bottom, leftward
      H[bl - r - 1] = [e[1], e[0]];
      P[bl] = e[2];
      if (!c) {  // left, upward
        e = next(bl, tl, bl);
        V[tl] = [e[1], e[0]];
      }
      tensor[tl - r] = numbers(attribute(patch[0], 'tensor'));
    }));
    return {C, R, P, H, V, colour, tensor, bicubic: attr('type') == 'bicubic',
            affine: parseTransform(attr('gradientTransform'))};
  }

  function hrefTarget(el) {
    const h = el.getAttribute('href') || el.getAttribute('xlink:href');
    return h && h[0] == '#' && elementById(el, h.slice(1));
  }

  // ---- Colour slopes -----------------------------------------------------------------------

  // The SVG 2 bicubic rule along one line of corners (positions `pos`, colours `col`): per
  // corner the slope g of each channel (colour per unit length), and the chords L.
  function lineSlopes(pos, col) {
    const N = pos.length - 1, L = [];
    for (let n = 0; n < N; n++) L[n] = hypot(pos[n + 1][0] - pos[n][0], pos[n + 1][1] - pos[n][1]);
    const interior = (k, ch) => {
      if (!(L[k - 1] > 0 && L[k] > 0)) return 0;
      const before = col[k - 1][ch], at = col[k][ch], after = col[k + 1][ch];
      if ((before < at && at > after) || (before > at && at < after)) return 0;  // extremum
      const sb = (at - before) / L[k - 1], sa = (after - at) / L[k];
      let s = (sb + sa) / 2;
      if (abs(s) > abs(3 * sb)) s = 3 * sb;
      if (abs(s) > abs(3 * sa)) s = 3 * sa;
      return s;
    };
    // Parabolic ends: 2δ − g of the neighbour; with one patch the last end sees g_0 unset (0).
    const end = (edge, k, ch) => !(L[edge] > 0) ? 0 : N == 1 && k ? 0 :
      2 * (col[edge + 1][ch] - col[edge][ch]) / L[edge] - (N == 1 ? 0 : interior(k ? N - 1 : 1, ch));
    const g = [];
    for (let n = 0; n <= N; n++)
      g[n] = [0, 1, 2].map((ch) => n == 0 ? end(0, 0, ch) : n == N ? end(N - 1, 1, ch) : interior(n, ch));
    return {g, L};
  }

  // Per patch k, 36 numbers from 36 k: for its corners (a, b) in the order 00, 01, 10, 11, the
  // colour and its slopes along s and along t per unit of the patch parameter (3 each), from
  // the rows' and the columns' lines.
  function patchColours(mesh) {
    const {C, R, P, colour} = mesh, W = C + 1;
    const line = (at) => lineSlopes(at.map((k) => P[k]), at.map((k) => colour[k] || [0, 0, 0]));
    const range = (count, f) => [...Array(count).keys()].map(f);
    const rows = range(R + 1, (r) => line(range(W, (n) => r * W + n)));
    const cols = range(W, (c) => line(range(R + 1, (n) => n * W + c)));
    const out = mesh.colours = new F64(36 * R * C);
    for (let r = 0, o = 0; r < R; r++)
      for (let c = 0; c < C; c++)
        for (let a = 0; a < 2; a++)
          for (let b = 0; b < 2; b++, o += 9)
            for (let ch = 0; ch < 3; ch++) {
              out[o + ch] = (colour[(r + b) * W + c + a] || [0, 0, 0])[ch];
              out[o + 3 + ch] = rows[r + b].L[c] * rows[r + b].g[c + a][ch];
              out[o + 6 + ch] = cols[c + a].L[r] * cols[c + a].g[r + b][ch];
            }
  }

  // ---- Tessellation ------------------------------------------------------------------------

  // The 4×4 control nets of the patches, 32 numbers per patch from 32 k: point q[a][b] (a along
  // s) at 8 a + 2 b, in the meshgradient's coordinates.
  function controlNets(mesh) {
    const {C, R, P, H, V} = mesh, W = C + 1, Q = mesh.Q = new F64(32 * R * C);
    for (let r = 0; r < R; r++)
      for (let c = 0; c < C; c++) {
        const t = mesh.tensor[r * C + c], top = H[r * C + c], bottom = H[(r + 1) * C + c], left = V[r * W + c];
        const right = V[r * W + c + 1];
        const corners = [P[r * W + c], P[r * W + c + 1], P[(r + 1) * W + c + 1], P[(r + 1) * W + c]];
        const q = [[corners[0], left[0], left[1], corners[3]], [top[0], , , bottom[0]],
                   [top[1], , , bottom[1]], [corners[1], right[0], right[1], corners[2]]];
        // Interior points next to corners 00, 30, 33, 03, as `tensor` lists them.
        [[1, 1], [2, 1], [2, 2], [1, 2]].forEach(([a, b], k) => {
          q[a][b] = t.length > 7 ? [corners[k][0] + t[2 * k], corners[k][1] + t[2 * k + 1]] :
            coonsInterior(q, a > 1, b > 1);
        });
        Q.set(q.flat(2), 32 * (r * C + c));
      }
  }

  // The interior point of a Coons patch written as a tensor patch, next to corner
  // q[mirrorS ? 3 : 0][mirrorT ? 3 : 0] (PDF reference, type 6 shading as type 7): weights
  // (ninths) of the boundary points [a, b].
  const COONS = [[0, 0, -4], [1, 0, 6], [0, 1, 6], [3, 0, -2], [0, 3, -2], [1, 3, 3], [3, 1, 3], [3, 3, -1]];
  function coonsInterior(q, mirrorS, mirrorT) {
    const p = [0, 0];
    for (const [a, b, w] of COONS) {
      const v = q[mirrorS ? 3 - a : a][mirrorT ? 3 - b : b];
      p[0] += w * v[0] / 9;
      p[1] += w * v[1] / 9;
    }
    return p;
  }

  // Cells along s (along = 0) or t (1) that keep patch k's triangles within the tolerances:
  // for the position from its control net q (device px) by the second differences and twists,
  // for the colour from the Hermite data (basis second derivatives are at most 6 for values, 4
  // for slopes), but no smaller than SMALLEST_CELL for the colour's sake.
  function cellsFor(bicubic, q, colours, k, along) {
    const x = (i, j, c) => q[32 * k + 2 * (along ? 4 * j + i : 4 * i + j) + c];
    const d = (f) => hypot(f(0), f(1));
    let bend = 0, twist = 0, length = 0, colour = 0;
    for (let j = 0; j < 4; j++)
      for (let i = 0; i < 3; i++) {
        length = max(length, 3 * d((c) => x(i + 1, j, c) - x(i, j, c)));
        if (i < 2) bend = max(bend, d((c) => x(i + 2, j, c) - 2 * x(i + 1, j, c) + x(i, j, c)));
        if (j < 3) twist = max(twist, d((c) => x(i + 1, j + 1, c) - x(i + 1, j, c) - x(i, j + 1, c) + x(i, j, c)));
      }
    for (let b = 0; b < 2 && bicubic; b++)
      for (let ch = 0; ch < 3; ch++) {
        // Corners (0, b) and (1, b) along s, (b, 0) and (b, 1) along t, and their slopes.
        const c0 = 36 * k + 9 * (along ? 2 * b : b) + ch, c1 = c0 + (along ? 9 : 18), s = along ? 6 : 3;
        colour = max(colour, 6 * abs(colours[c1] - colours[c0]) + 4 * abs(colours[c0 + s]) + 4 * abs(colours[c1 + s]));
      }
    const n = max(sqrt((6 * bend + 9 * twist) / (4 * POSITION_TOLERANCE)),
                       min(sqrt(colour / (8 * COLOUR_TOLERANCE)), length / SMALLEST_CELL));
    return min(MAX_CELLS, ceil(n) || 1);
  }

  // For u = a / n (a = 0 … n), 8 numbers from 8 a: the cubic Bernstein basis and the colour's
  // basis (bicubic: Hermite for two values and two slopes; bilinear: 1 − u, u). Made once per
  // n and kind.
  const bases = [];
  const basis = (n, bicubic) => bases[2 * n + bicubic] ||= basisTable(n, bicubic);
  function basisTable(n, bicubic) {
    const table = [];
    for (let a = 0, u = 0, v = 1; a <= n; v = 1 - (u = ++a / n))
      table.push(v * v * v, 3 * u * v * v, 3 * u * u * v, u * u * u,
        ...(bicubic ? [v * v * (1 + 2 * u), u * u * (3 - 2 * u), u * v * v, -u * u * v] : [v, u, 0, 0]));
    return table;
  }

  // The meshgradient as triangles through the affine transform m (device pixels): vertices
  // (x, y and the colour r, g, b 0–1, 5 numbers each) and vertex indices, each patch a grid of
  // cells of its own. Where two neighbours are cut differently, the chords of their shared edge
  // part by at most twice the position tolerance; their skirts cover any pixel centre between
  // them. The skirts' triangles come first, so the patches' own are drawn over them.
  function tessellate({Q, colours, bicubic}, m) {
    const count = Q.length / 32, q = new F64(Q.length), cuts = new Uint8Array(2 * count);
    const points = new F64(8), colour = new F64(12);
    let cells = 0, v = 0, n, skirt = 0;
    for (let i = 0; i < Q.length; i += 2) {
      q[i] = m[0] * Q[i] + m[2] * Q[i + 1] + m[4];
      q[i + 1] = m[1] * Q[i] + m[3] * Q[i + 1] + m[5];
    }
    for (let k = 0; k < count; k++) {
      const ns = cuts[2 * k] = cellsFor(bicubic, q, colours, k, 0), nt = cuts[2 * k + 1] = cellsFor(bicubic, q, colours, k, 1);
      // At least the grid's vertices and two per border vertex, and its cells and a quad per
      // border edge (the triangles of vertex 0 left over are empty).
      cells += (ns + 5) * (nt + 5);
    }
    const xy = new Float32Array(5 * cells), indices = new Uint32Array(n = 6 * cells);
    for (let k = 0; k < count; k++) {
      const ns = cuts[2 * k], nt = cuts[2 * k + 1], S = basis(ns, bicubic), T = basis(nt, bicubic), o = 32 * k;
      for (let b = 0; b <= nt; b++) {
        // The patch at this t: control points along s, and for the corner columns i = 0, 1 the
        // colour and its slope along s (colour[6 i], colour[6 i + 3]).
        const t = 8 * b;
        for (let i = 0; i < 8; i++) {
          const e = o + 4 * i - 3 * (i % 2);  // q[i >> 1][0], coordinate i % 2
          points[i] = T[t] * q[e] + T[t + 1] * q[e + 2] + T[t + 2] * q[e + 4] + T[t + 3] * q[e + 6];
        }
        for (let i = 0; i < 6; i++) {
          const c = 36 * k + 18 * (i > 2) + i % 3;  // corner (i > 2, 0), channel i % 3
          colour[i + 3 * (i > 2)] = T[t + 4] * colours[c] + T[t + 5] * colours[c + 9] + T[t + 6] * colours[c + 6] +
            T[t + 7] * colours[c + 15];
          colour[i + 3 + 3 * (i > 2)] = T[t + 4] * colours[c + 3] + T[t + 5] * colours[c + 12];
        }
        for (let a = 0; a <= ns; a++, v++) {
          const s = 8 * a;
          for (let c = 0; c < 2; c++)
            xy[5 * v + c] = S[s] * points[c] + S[s + 1] * points[2 + c] + S[s + 2] * points[4 + c] + S[s + 3] * points[6 + c];
          for (let ch = 0; ch < 3; ch++)
            xy[5 * v + 2 + ch] = S[s + 4] * colour[ch] + S[s + 5] * colour[6 + ch] + S[s + 6] * colour[3 + ch] +
              S[s + 7] * colour[9 + ch];
          if (a < ns && b < nt) {  // the cell's two triangles, from the end of indices
            n -= 6;
            indices[n] = indices[n + 3] = v;
            indices[n + 1] = v + 1;
            indices[n + 2] = indices[n + 4] = v + ns + 2;
            indices[n + 5] = v + ns + 1;
          }
        }
      }
      skirt = addSkirt(xy, indices, v - (ns + 1) * (nt + 1), ns, v, skirt);
      v += 4 * (ns + nt);
    }
    return {xy, indices};
  }

  // The skirt of the patch whose (ns + 1)-wide grid of vertices starts at `grid`: its border
  // vertices each moved SKIRT px both ways along the border's normal, keeping their colour, as
  // vertices from v on, and quads between them as indices from `at` on; returns their end.
  function addSkirt(xy, indices, grid, ns, v, at) {
    const border = [], W = ns + 1, nt = (v - grid) / W - 1;
    for (let side = 0, a = 0, b = 0; side < 4; side++)  // along s, then t, then back
      for (let i = side % 2 ? nt : ns; i--; side % 2 ? b += 2 - side : a += 1 - side) border.push(grid + b * W + a);
    border.forEach((p, i) => {
      const next = 5 * border[(i + 1) % border.length], previous = 5 * border.at(i - 1);
      const dx = xy[next] - xy[previous], dy = xy[next + 1] - xy[previous + 1], f = SKIRT / (hypot(dx, dy) || 1e9);
      for (let side = -1; side < 2; side += 2, v++) {
        xy.copyWithin(5 * v, 5 * p, 5 * p + 5);
        xy[5 * v] -= side * f * dy;
        xy[5 * v + 1] += side * f * dx;
      }
      const here = v - 2, there = here + 2 * ((i + 1) % border.length - i);  // the next vertex's pair
      indices.set([here, here + 1, there, here + 1, there + 1, there], at);
      at += 6;
    });
    return at;
  }

  // ---- Drawing -----------------------------------------------------------------------------

  // Draws the triangles into the RGBA pixels (w wide) in script (the canvas 2D fallback): every
  // pixel whose centre a triangle covers (edges included) gets the colour interpolated there.
  // The triangles lie within the pixels' rows (a write outside a typed array is ignored).
  function drawSoftware({xy, indices}, pixels, w) {
    for (let k = 0; k < indices.length; k += 3) {
      const i0 = 5 * indices[k], i1 = 5 * indices[k + 1], i2 = 5 * indices[k + 2], x0 = xy[i0], y0 = xy[i0 + 1];
      const dx1 = xy[i1] - x0, dy1 = xy[i1 + 1] - y0, dx2 = xy[i2] - x0, dy2 = xy[i2 + 1] - y0;
      const area = dx1 * dy2 - dx2 * dy1, xe = min(w, x0 + max(0, dx1, dx2)), ye = y0 + max(0, dy1, dy2);
      for (let y = floor(y0 + min(0, dy1, dy2)); area && y < ye; y++)
        for (let x = max(0, floor(x0 + min(0, dx1, dx2))); x < xe; x++) {
          // Barycentric weights of vertices 1 and 2 at the pixel centre.
          const px = x + 0.5 - x0, py = y + 0.5 - y0;
          const w1 = (px * dy2 - dx2 * py) / area, w2 = (dx1 * py - px * dy1) / area, w0 = 1 - w1 - w2;
          if (min(w0, w1, w2) < 0) continue;
          const o = 4 * (y * w + x);
          for (let ch = 0; ch < 3; ch++)
            pixels[o + ch] = 255 * (w0 * xy[i0 + 2 + ch] + w1 * xy[i1 + 2 + ch] + w2 * xy[i2 + 2 + ch]);  // rounded by the array
          pixels[o + 3] = 255;
        }
    }
  }

  // ---- Shapes ------------------------------------------------------------------------------

  // The box [x0, y0, x1, y1] of the points [x, y, x, y, …] through m.
  function box(points, m) {
    const b = [Infinity, Infinity, -Infinity, -Infinity];
    for (let i = 0; i < points.length; i += 2) {
      const x = m[0] * points[i] + m[2] * points[i + 1] + m[4], y = m[1] * points[i] + m[3] * points[i + 1] + m[5];
      b[0] = min(b[0], x);
      b[1] = min(b[1], y);
      b[2] = max(b[2], x);
      b[3] = max(b[3], y);
    }
    return b;
  }

  // What drawing one shape's mesh at the resolution it is shown at takes: its transform to
  // device pixels m and the device box [x, y, w, h] drawn; nothing if that has not changed.
  function job(record) {
    const ctm = record.meshShape.getScreenCTM(), ratio = devicePixelRatio;
    if (!ctm) return;  // not rendered
    let m = [...'abcdef'].map((k) => ctm[k] * ratio);
    if (record.key == (record.key = m.join())) return;
    const mesh = record.mesh;
    let b = box(mesh.Q, multiply(m, mesh.affine));
    const side = MAX_SIDE - 8;  // room for the skirts and the margins
    const shrink = min(1, side / (b[2] - b[0]), side / (b[3] - b[1]),
                            sqrt(MAX_AREA / (b[2] - b[0] + 1) / (b[3] - b[1] + 1)));
    if (!(shrink > 0)) return;
    m = m.map((v) => v * shrink);
    b = b.map((v) => v * shrink);
    const x = floor(b[0]) - 3, y = floor(b[1]) - 3;  // room for the skirts
    return {record, m, x, y, w: ceil(b[2]) + 3 - x, h: ceil(b[3]) + 3 - y};
  }

  // The RGBA pixels (w × h, top row first) as a BMP, which browsers decode with their alpha
  // (a BITMAPV4HEADER with bit masks in the pixels' byte order): making it costs one header,
  // where the canvas's PNG encoder compresses (far slower for a whole image's meshes) and a
  // data: URL is base64. Returns a blob: URL.
  function encodeBmp(pixels, w, h) {
    const head = new DataView(new ArrayBuffer(122));
    // 'BM', the file's size, the pixels' offset; the header's size, w, −h (top-down), 1 plane
    // of 32 bits, bit fields: the masks of R, G, B, A; the sRGB colour space.
    [[0, 0x4d42 | pixels.length + 122 << 16], [4, pixels.length + 122 >> 16], [10, 122], [14, 108], [18, w],
     [22, -h], [26, 0x200001], [30, 3], [54, 255], [58, 0xff00], [62, 0xff0000], [66, -1 << 24],
     [70, 0x73524742]].forEach(([at, value]) => head.setInt32(at, value, 1));
    return URL.createObjectURL(new Blob([head, pixels], {type: 'image/bmp'}));
  }

  // Draws each job's triangles into pixels of its own, encodes them and paints the shape with
  // them.
  function drawAll(jobs) {
    for (const j of jobs) {
      const {w, h, record: {mesh}} = j, pixels = new Uint8ClampedArray(4 * w * h);
      drawSoftware(tessellate(mesh, multiply([1, 0, 0, 1, -j.x, -j.y], multiply(j.m, mesh.affine))), pixels, w);
      paint(j, encodeBmp(pixels, w, h));
    }
  }

  const drawRecords = (list) => drawAll(list.map(job).filter((j) => j));

  // Paints the shape with the image: a pattern in device pixels (patternTransform maps them to
  // the shape's user space) whose one tile holds the shape's whole box, so that no second copy
  // of the image shows inside the shape.
  function paint({record, m, x, y, w, h}, url) {
    if (!record.tile) {
      record.tile = create('pattern', SVG_NS);
      record.tileImage = record.tile.appendChild(create('image', SVG_NS));
      record.tile.id = 'gradmesh-' + ++patternCount;
      record.gradient.before(record.tile);
      record.meshShape.style.fill = `url(#${record.tile.id})`;
    }
    const {x: left, y: top, width, height} = record.meshShape.getBBox();
    const tile = box([left, top, left + width, top + height, left, top + height, left + width, top], m);
    const tx = floor(tile[0]) - 2, ty = floor(tile[1]) - 2;
    const set = (el, values) => Object.entries(values).forEach(([name, value]) => el.setAttribute(name, value));
    set(record.tile, {patternUnits: 'userSpaceOnUse', patternTransform: new DOMMatrix(m).inverse(), x: tx, y: ty,
                         width: ceil(tile[2]) + 2 - tx, height: ceil(tile[3]) + 2 - ty});
    URL.revokeObjectURL(record.tileImage.getAttribute('href'));  // the image drawn before, if any
    set(record.tileImage, {x: x - tx, y: y - ty, width: w, height: h, href: url});  // tile-relative
  }

  // Finds the shapes painted with a meshgradient that are not drawn yet, and draws them.
  function scan() {
    const started = performance.now(), found = [];
    for (const shape of document.querySelectorAll('path,rect,circle,ellipse,polygon,polyline')) {
      const id = !shape.gradmeshRecord && shape.namespaceURI == SVG_NS && paintedId(shape);
      const gradient = id && elementById(shape, id);
      if (!gradient || gradient.localName != 'meshgradient') continue;
      const mesh = gradient.gradmeshMesh || (gradient.gradmeshMesh = parseMesh(gradient));
      if (!mesh.C) continue;
      if (!mesh.Q) {
        patchColours(mesh);
        controlNets(mesh);
      }
      records.push(shape.gradmeshRecord = {meshShape: shape, gradient, mesh});
      found.push(shape.gradmeshRecord);
    }
    drawRecords(found);
    if (options.timing && found.length)
      console.log(`gradmesh ${found.length} meshes ${performance.now() - started} ms`);
  }

  // Draws again every mesh whose transform to the screen has changed (zoom, resize).
  const redraw = () => drawRecords(records);

  window.gradmeshMeshes = {scan, redraw, mode: '2d'};
  let pending = 0;
  addEventListener('resize', () => pending || (pending = requestAnimationFrame(() => redraw(pending = 0))));
  if (document.readyState == 'loading') document.addEventListener('DOMContentLoaded', scan);
  scan();
})();
