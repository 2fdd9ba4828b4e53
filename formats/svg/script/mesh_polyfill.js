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
    const rgb = hex ? null : numbers(getComputedStyle(source.querySelectorAll('stop')[index]).stopColor);
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
  // its attributes, then per stop the markup of its attributes and its index in `source`. Tags
  // may carry a namespace prefix (`<svg:stop>`, as some tools write).
  function meshRows(source) {
    const rows = [];
    let patch = [], index = 0;
    for (const [, name, attributes] of source.outerHTML.matchAll(/<(?:\w+:)?(meshrow|meshpatch|stop)\b([^>]*)/g))
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

  // The SVG 2 bicubic rule along the line of corners `at` (indices into P and into rgb, the
  // corners' colours, 3 numbers each): per segment n of the line, the slope g of each channel
  // (colour per unit length) at its start and at its end times its chord L (6 numbers from 6 n).
  function lineSlopes(at, P, rgb) {
    const N = at.length - 1, L = [], g = new F64(3 * N + 3), out = new F64(6 * N);
    for (let n = 0; n < N; n++) L[n] = hypot(P[at[n + 1]][0] - P[at[n]][0], P[at[n + 1]][1] - P[at[n]][1]);
    const col = (n, ch) => rgb[3 * at[n] + ch];
    const interior = (k, ch) => {
      if (!(L[k - 1] > 0 && L[k] > 0)) return 0;
      const before = col(k - 1, ch), here = col(k, ch), after = col(k + 1, ch);
      if ((before < here && here > after) || (before > here && here < after)) return 0;  // extremum
      const sb = (here - before) / L[k - 1], sa = (after - here) / L[k];
      let s = (sb + sa) / 2;
      if (abs(s) > abs(3 * sb)) s = 3 * sb;
      if (abs(s) > abs(3 * sa)) s = 3 * sa;
      return s;
    };
    // Parabolic ends: 2δ − g of the neighbour; with one patch the last end sees g_0 unset (0).
    const end = (edge, k, ch) => !(L[edge] > 0) ? 0 : N == 1 && k ? 0 :
      2 * (col(edge + 1, ch) - col(edge, ch)) / L[edge] - (N == 1 ? 0 : interior(k ? N - 1 : 1, ch));
    for (let n = 0; n <= N; n++)
      for (let ch = 0; ch < 3; ch++) g[3 * n + ch] = n == 0 ? end(0, 0, ch) : n == N ? end(N - 1, 1, ch) : interior(n, ch);
    for (let n = 0; n < N; n++)
      for (let i = 0; i < 6; i++) out[6 * n + i] = L[n] * g[3 * n + i];
    return out;
  }

  // Per patch k, 36 numbers from 36 k: for its corners (a, b) in the order 00, 01, 10, 11, the
  // colour and its slopes along s and along t per unit of the patch parameter (3 each), from
  // the rows' and the columns' lines.
  function patchColours(mesh) {
    const {C, R, P, colour} = mesh, W = C + 1, rgb = new F64(3 * W * (R + 1));
    colour.forEach((c, i) => rgb.set(c, 3 * i));  // a corner without a colour is black
    const range = (count, f) => [...Array(count).keys()].map(f);
    const rows = range(R + 1, (r) => lineSlopes(range(W, (n) => r * W + n), P, rgb));
    const cols = range(W, (c) => lineSlopes(range(R + 1, (n) => n * W + c), P, rgb));
    const out = mesh.colours = new F64(36 * R * C);
    for (let r = 0, o = 0; r < R; r++)
      for (let c = 0; c < C; c++)
        for (let a = 0; a < 2; a++)
          for (let b = 0; b < 2; b++, o += 9)
            for (let ch = 0; ch < 3; ch++) {
              out[o + ch] = rgb[3 * ((r + b) * W + c + a) + ch];
              out[o + 3 + ch] = rows[r + b][6 * c + 3 * a + ch];
              out[o + 6 + ch] = cols[c + a][6 * r + 3 * b + ch];
            }
  }

  // ---- Tessellation ------------------------------------------------------------------------

  // The 4×4 control nets of the patches, 32 numbers per patch from 32 k: point q[a][b] (a along
  // s) at 8 a + 2 b, in the meshgradient's coordinates.
  function controlNets(mesh) {
    const {C, R, P, H, V, tensor} = mesh, W = C + 1, Q = mesh.Q = new F64(32 * R * C);
    for (let r = 0, k = 0; r < R; r++)
      for (let c = 0; c < C; c++, k++) {
        const o = 32 * k, t = tensor[k], top = H[k], bottom = H[k + C], left = V[r * W + c], right = V[r * W + c + 1];
        // The boundary points, column by column (the holes are the interior points).
        [P[r * W + c], left[0], left[1], P[(r + 1) * W + c], top[0], , , bottom[0], top[1], , , bottom[1],
         P[r * W + c + 1], right[0], right[1], P[(r + 1) * W + c + 1]].forEach((p, i) => Q.set(p, o + 2 * i));
        // Interior points next to corners 00, 30, 33, 03, as `tensor` lists them: the corner
        // plus the tensor's offset, else the interior point of the Coons patch (PDF reference,
        // type 6 shading as type 7) from the boundary points as COONS weighs them (ninths).
        [0, 24, 30, 6].forEach((corner, n) => {
          const mirrorS = corner > 8, mirrorT = corner % 8 > 0, at = o + (mirrorS ? 16 : 8) + (mirrorT ? 4 : 2);
          for (let d = 0; d < 2; d++)
            Q[at + d] = t.length > 7 ? Q[o + corner + d] + t[2 * n + d] : COONS.reduce((sum, [a, b, w]) =>
              sum + w * Q[o + 8 * (mirrorS ? 3 - a : a) + 2 * (mirrorT ? 3 - b : b) + d] / 9, 0);
        });
      }
  }

  const COONS = [[0, 0, -4], [1, 0, 6], [0, 1, 6], [3, 0, -2], [0, 3, -2], [1, 3, 3], [3, 1, 3], [3, 3, -1]];

  // Cells along s (along = 0) or t (1) that keep patch k's triangles within the tolerances:
  // for the position from its control net q (device px) by the second differences and twists,
  // for the colour from the Hermite data (basis second derivatives are at most 6 for values, 4
  // for slopes), but no smaller than SMALLEST_CELL for the colour's sake.
  function cellsFor(bicubic, q, colours, k, along) {
    // Point (i, j) of the net, i along the direction, is at p + i di + j dj.
    const di = along ? 2 : 8, dj = 10 - di, square = (x, y) => x * x + y * y;
    let bend = 0, twist = 0, length = 0, colour = 0;
    for (let j = 0, p; j < 4; j++)
      for (let i = 0; i < 3; i++) {
        p = 32 * k + i * di + j * dj;
        length = max(length, square(q[p + di] - q[p], q[p + di + 1] - q[p + 1]));
        if (i < 2) bend = max(bend, square(q[p + 2 * di] - 2 * q[p + di] + q[p], q[p + 2 * di + 1] - 2 * q[p + di + 1] + q[p + 1]));
        if (j < 3) twist = max(twist, square(q[p + di + dj] - q[p + di] - q[p + dj] + q[p],
          q[p + di + dj + 1] - q[p + di + 1] - q[p + dj + 1] + q[p + 1]));
      }
    for (let b = 0; b < 2 && bicubic; b++)
      for (let ch = 0; ch < 3; ch++) {
        // Corners (0, b) and (1, b) along s, (b, 0) and (b, 1) along t, and their slopes.
        const c0 = 36 * k + 9 * (along ? 2 * b : b) + ch, c1 = c0 + (along ? 9 : 18), s = along ? 6 : 3;
        colour = max(colour, 6 * abs(colours[c1] - colours[c0]) + 4 * abs(colours[c0 + s]) + 4 * abs(colours[c1 + s]));
      }
    const n = max(sqrt((6 * sqrt(bend) + 9 * sqrt(twist)) / (4 * POSITION_TOLERANCE)),
                       min(sqrt(colour / (8 * COLOUR_TOLERANCE)), 3 * sqrt(length) / SMALLEST_CELL));
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

  // Vertices hold x and y in fixed point (FIXED units a device pixel, so that the triangles'
  // edge functions are exact integers) and the colour r, g, b 0–255: 5 numbers each.
  const FIXED = 256;

  // Draws the meshgradient through the affine transform m (device pixels) into the RGBA pixels
  // (w × h): each patch is a grid of cells of its own, two triangles each. Neighbours cut alike
  // share their edge's vertices exactly, and the triangles' fill rule leaves no pixel centre
  // between them. Where two neighbours are cut differently, the chords of their shared edge
  // part by at most twice the position tolerance: both sides get a skirt there, as does every
  // side on the mesh's outline.
  function drawMesh({Q, colours, bicubic, C, R}, m, job) {
    const count = Q.length / 32, q = new F64(Q.length), cuts = new Uint8Array(2 * count);
    const points = new F64(8), colour = new F64(12), grid = new F64(5 * (MAX_CELLS + 1) ** 2 + 20);
    for (let i = 0; i < Q.length; i += 2) {
      q[i] = m[0] * Q[i] + m[2] * Q[i + 1] + m[4];
      q[i + 1] = m[1] * Q[i] + m[3] * Q[i + 1] + m[5];
    }
    for (let k = 0; k < count; k++) {
      cuts[2 * k] = cellsFor(bicubic, q, colours, k, 0);
      cuts[2 * k + 1] = cellsFor(bicubic, q, colours, k, 1);
    }
    const fill = (i, j, k, under) => fillTriangle(grid, i, j, k, job, under);
    for (let k = 0, row = 0, column = 0; k < count; k++, ++column < C || (column = 0, row++)) {
      const ns = cuts[2 * k], nt = cuts[2 * k + 1], S = basis(ns, bicubic), T = basis(nt, bicubic), o = 32 * k;
      for (let b = 0, v = 0; b <= nt; b++) {
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
        for (let a = 0; a <= ns; a++, v += 5) {
          const s = 8 * a;
          for (let c = 0; c < 2; c++)
            grid[v + c] = Math.round(FIXED * (S[s] * points[c] + S[s + 1] * points[2 + c] + S[s + 2] * points[4 + c] +
              S[s + 3] * points[6 + c]));
          for (let ch = 0; ch < 3; ch++)
            grid[v + 2 + ch] = 255 * (S[s + 4] * colour[ch] + S[s + 5] * colour[6 + ch] + S[s + 6] * colour[3 + ch] +
              S[s + 7] * colour[9 + ch]);
          if (a && b) {  // the cell whose bottom right corner this is
            const above = v - 5 * (ns + 1);
            fill(above - 5, above, v, 0);
            fill(above - 5, v, v - 5, 0);
          }
        }
      }
      // Skirts: top, bottom (along s), left, right (along t).
      const W = 5 * (ns + 1), bottom = W * nt;
      if (!row || cuts[2 * k - 2 * C] != ns) skirt(0, 5, ns);
      if (row == R - 1 || cuts[2 * k + 2 * C] != ns) skirt(bottom, 5, ns);
      if (!column || cuts[2 * k - 1] != nt) skirt(0, W, nt);
      if (column == C - 1 || cuts[2 * k + 3] != nt) skirt(W - 5, W, nt);
    }

    // The skirt along n segments of the grid's vertices from `first` on, `step` apart: each
    // segment a quad SKIRT px to either side of it and beyond its ends, the colours of its ends.
    function skirt(first, step, n) {
      for (let i = 0, p = first, e = grid.length - 20; i < n; i++, p += step) {
        const dx = grid[p + step] - grid[p], dy = grid[p + step + 1] - grid[p + 1], f = FIXED * SKIRT / (hypot(dx, dy) || 1e9);
        const ux = f * dx, uy = f * dy;
        // Four vertices at the end of the grid's scratch space: the start's two, the end's two.
        for (let v = 0; v < 4; v++) {
          const from = v < 2 ? p : p + step, side = v % 2 ? 1 : -1, along = v < 2 ? -1 : 1;
          grid.copyWithin(e + 5 * v, from, from + 5);
          grid[e + 5 * v] = Math.round(grid[from] + along * ux - side * uy);
          grid[e + 5 * v + 1] = Math.round(grid[from + 1] + along * uy + side * ux);
        }
        fill(e, e + 5, e + 15, 1);
        fill(e, e + 15, e + 10, 1);
      }
    }
  }

  // Fills the triangle of vertices i, j, k (offsets in `vertices`) into the job's RGBA pixels:
  // every pixel whose centre it covers, its edges included, gets the colour interpolated there;
  // `under`: only pixels that nothing has painted yet (a skirt under the patches). The edge
  // functions are exact (integers in fixed point), so that triangles that share an edge leave
  // no pixel centre between them. Where the job continues the piece before it (`before`), each
  // pixel is painted in one of the two: a patch's takes it from the other piece, a skirt leaves
  // it to the other piece if that painted it.
  function fillTriangle(vertices, i, j, k, {pixels, w, h, x: left, y: top, before}, under) {
    const x0 = vertices[i], y0 = vertices[i + 1], x1 = vertices[j], y1 = vertices[j + 1], x2 = vertices[k], y2 = vertices[k + 1];
    const area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0), sign = area < 0 ? -1 : 1, half = FIXED / 2;
    if (!area) return;
    // Edge function e_n = A_n x + B_n y + C_n: |area| at vertex n, 0 on the opposite edge.
    const A0 = sign * (y1 - y2), B0 = sign * (x2 - x1), C0 = sign * (x1 * y2 - x2 * y1);
    const A1 = sign * (y2 - y0), B1 = sign * (x0 - x2), C1 = sign * (x2 * y0 - x0 * y2);
    const A2 = sign * (y0 - y1), B2 = sign * (x1 - x0), C2 = sign * (x0 * y1 - x1 * y0);
    const xs = max(0, ceil((min(x0, x1, x2) - half) / FIXED)), xe = min(w - 1, floor((max(x0, x1, x2) - half) / FIXED));
    const ye = min(h - 1, floor((max(y0, y1, y2) - half) / FIXED)), weight = 1 / abs(area);
    for (let y = max(0, ceil((min(y0, y1, y2) - half) / FIXED)); y <= ye; y++) {
      const px = FIXED * xs + half, py = FIXED * y + half, yb = before && y + top - before.y;
      let e0 = A0 * px + B0 * py + C0, e1 = A1 * px + B1 * py + C1, e2 = A2 * px + B2 * py + C2;
      for (let x = xs, o = 4 * (y * w + x); x <= xe; x++, o += 4, e0 += FIXED * A0, e1 += FIXED * A1, e2 += FIXED * A2) {
        if (e0 < 0 || e1 < 0 || e2 < 0 || under && pixels[o + 3]) continue;
        const xb = before && x + left - before.x, q = before && 4 * (yb * before.w + xb) + 3;
        if (before && yb >= 0 && yb < before.h && xb >= 0 && xb < before.w) {
          if (under && before.pixels[q]) continue;
          if (!under) before.pixels[q] = 0;
        }
        for (let ch = 2; ch < 5; ch++)
          pixels[o + ch - 2] = weight * (e0 * vertices[i + ch] + e1 * vertices[j + ch] + e2 * vertices[k + ch]);  // rounded by the array
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

  // Draws each job's triangles into pixels of its own, then encodes them and paints the shapes
  // with them. A job whose mesh continues the one before it (the pieces of a mesh with holes, as
  // our SVGs hold them) shares the pixels along their common row with it (fillTriangle).
  function drawAll(jobs) {
    jobs.forEach((j, k) => {
      const {w, h, record: {mesh}} = j, previous = jobs[k - 1];
      j.pixels = new Uint8ClampedArray(4 * w * h);
      j.before = previous && continues(previous, j) && previous;
      drawMesh(mesh, multiply([1, 0, 0, 1, -j.x, -j.y], multiply(j.m, mesh.affine)), j);
    });
    for (const j of jobs) paint(j, encodeBmp(j.pixels, j.w, j.h));
  }

  // Whether job b's mesh continues job a's below it: as many patch columns, and the first row
  // of b's corners starts and ends where a's last row does, on the screen.
  function continues(a, b) {
    const corner = ({m, record: {mesh}}, k) => box(mesh.P[k], multiply(m, mesh.affine));
    const A = a.record.mesh, B = b.record.mesh, last = A.R * (A.C + 1);
    return A.C == B.C && [0, A.C].every((c) =>
      hypot(...corner(a, last + c).slice(0, 2).map((v, n) => v - corner(b, c)[n])) < 0.01);
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
