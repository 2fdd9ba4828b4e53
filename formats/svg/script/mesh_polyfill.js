// gradmesh mesh script: draws SVG 2 <meshgradient> fills in browsers that implement none.
//
// Every SVG gradmesh writes with meshes ends with this script, minified (docs/browsers.md). For
// each shape painted with a meshgradient (fill="url(#id)" or style="fill:url(#id) ...") it
// tessellates the mesh's patches into small triangles with per-vertex colour, draws them at the
// device resolution of the shape's on-screen box (WebGL, else a software rasteriser into a 2D
// canvas), and paints the shape with the result as an <image> in a <pattern>: the browser's own
// path anti-aliasing still gives the outline.
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
// window.gradmeshMeshOptions, when set before, may ask for {noWebGL: true} (the 2D path) and
// {timing: true} (the draw time on the console).
(() => {
  if (window.SVGMeshGradientElement) return;  // native meshes
  if (window.gradmeshMeshes) return window.gradmeshMeshes.scan();

  const {abs, ceil, floor, max, min, sqrt} = Math;
  const hypot = (x, y) => sqrt(x * x + y * y);  // Math.hypot is several times slower
  const SVG_NS = 'http://www.w3.org/2000/svg', HTML_NS = 'http://www.w3.org/1999/xhtml';
  // Largest canvas side and area drawn (device pixels; a side WebGL implementations take in
  // practice); larger boxes are drawn coarser.
  const MAX_SIDE = 4096, MAX_AREA = 1 << 24;
  // Subdivision: position error (device px) and colour error (0–1) of the linear triangles,
  // the smallest cell (device px) the colour alone asks for, and the most cells per side.
  const POSITION_TOLERANCE = 0.2, COLOUR_TOLERANCE = 0.6 / 255, SMALLEST_CELL = 1.5;
  const MAX_CELLS = 64;
  // Pixels the drawn mesh is grown by, so that pixels on its border whose centre no triangle
  // covers are not transparent inside the anti-aliased path.
  const DILATION = 2;

  const options = window.gradmeshMeshOptions || {};
  const records = [];  // one per painted shape: {shape, gradient, mesh, pattern, image, key}
  let patternCount = 0;
  let gl;  // the shared WebGL context: undefined until tried, then {ctx, size} or null
  // WebGL enums (the minifier cannot shorten their names).
  const ARRAY_BUFFER = 34962, ELEMENT_ARRAY_BUFFER = 34963, STREAM_DRAW = 35040;

  // ---- Parsing ---------------------------------------------------------------------------

  const numbers = (text) => (text.match(/[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/g) || []).map(Number);
  const childrenNamed = (el, name) => [...el.children].filter((c) => c.localName == name);
  const styleOrAttribute = (el, name) =>
    (el.hasAttribute('style') && el.style.getPropertyValue(name)) || el.getAttribute(name);

  // The meshgradient id a shape's fill names.
  const paintedId = (shape) => (/url\(\s*['"]?[^#)]*#([^)'"\s]+)/.exec(styleOrAttribute(shape, 'fill')) || [])[1];

  // The element with `id`, looked up in the shape's outermost <svg> first: a page that inlines
  // several gradmesh SVGs repeats their ids.
  function elementById(el, id) {
    let root = el;
    while (root.ownerSVGElement) root = root.ownerSVGElement;
    return root.querySelector(`[id="${id}"]`) || document.getElementById(id);
  }

  // An sRGB colour 0–1 from a stop: #rgb or #rrggbb, else whatever the browser makes of it.
  function stopColour(stop) {
    const text = styleOrAttribute(stop, 'stop-color') || '#000';
    const hex = (/^\s*#([0-9a-f]{3}|[0-9a-f]{6})\b/i.exec(text) || [])[1];
    const rgb = hex ? null : numbers(getComputedStyle(stop).stopColor);
    return [0, 1, 2].map((k) => (rgb ? rgb[k] :
      parseInt(hex.length > 3 ? hex.substr(2 * k, 2) : hex[k] + hex[k], 16)) / 255);
  }

  // Affine transforms [a b c d e f] (x' = a x + c y + e, y' = b x + d y + f).
  const multiply = (m, t) => [m[0] * t[0] + m[2] * t[1], m[1] * t[0] + m[3] * t[1],
    m[0] * t[2] + m[2] * t[3], m[1] * t[2] + m[3] * t[3],
    m[0] * t[4] + m[2] * t[5] + m[4], m[1] * t[4] + m[3] * t[5] + m[5]];  // first t, then m
  const apply = (m, p) => [m[0] * p[0] + m[2] * p[1] + m[4], m[1] * p[0] + m[3] * p[1] + m[5]];

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

  // One stop's edge from `start`: [handle 1, handle 2, end]. A closing edge ends at the corner
  // `end` already known, and may leave its end point out.
  function parseEdge(stop, start, end) {
    const path = stop.getAttribute('path').trim(), v = numbers(path.slice(1));
    const point = (k) => (/[cl]/.test(path[0]) ? apply([1, 0, 0, 1, ...start], v.slice(2 * k)) :
      v.slice(2 * k, 2 * k + 2));
    if (/c/i.test(path[0])) return [point(0), point(1), v.length > 4 ? point(2) : end];
    if (v.length) end = point(0);
    return [lerp(start, end, 1 / 3), lerp(start, end, 2 / 3), end];
  }

  // The meshgradient (its href chain included) as a grid of C×R patches: corners P and their
  // colours, horizontal edge handles H (left corner first), vertical V (top first), tensor
  // points per patch.
  function parseMesh(gradient) {
    const chain = [gradient];
    for (let g = gradient; (g = hrefTarget(g)) && !chain.includes(g);) chain.push(g);
    const attr = (name) => (chain.find((g) => g.hasAttribute(name)) || gradient).getAttribute(name);
    const rows = childrenNamed(chain.find((g) => childrenNamed(g, 'meshrow').length) || gradient, 'meshrow');
    const R = rows.length, C = R && childrenNamed(rows[0], 'meshpatch').length, W = C + 1;
    const P = [[+attr('x') || 0, +attr('y') || 0]], H = [], V = [], colour = [], tensor = [];
    rows.forEach((row, r) => childrenNamed(row, 'meshpatch').slice(0, C).forEach((patch, c) => {
      const stops = childrenNamed(patch, 'stop'), tl = r * W + c, bl = tl + W;  // corner indices
      const next = (start, end, corner) => {  // the next stop: its edge and its start's colour
        const stop = stops.shift();
        if (corner >= 0) colour[corner] = stopColour(stop);
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
      tensor[tl - r] = numbers(patch.getAttribute('tensor') || '');
    }));
    return {C, R, P, H, V, colour, tensor, bicubic: attr('type') == 'bicubic',
            transform: parseTransform(attr('gradientTransform'))};
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

  // Per patch: the colours of its corners [a][b] and their slopes along s (S) and t (T) per
  // unit of the patch parameter, from the rows' and the columns' lines.
  function patchColours(mesh) {
    const {C, R, P, colour} = mesh, W = C + 1;
    const line = (count, index) => {
      const at = [...Array(count).keys()].map(index);
      return lineSlopes(at.map((k) => P[k]), at.map((k) => colour[k] || [0, 0, 0]));
    };
    const rows = [...Array(R + 1).keys()].map((r) => line(W, (n) => r * W + n));
    const cols = [...Array(W).keys()].map((c) => line(R + 1, (n) => n * W + c));
    const scaled = (f, v) => [f * v[0], f * v[1], f * v[2]];
    mesh.colours = [];
    for (let r = 0; r < R; r++)
      for (let c = 0; c < C; c++) {
        const corner = (a, b) => ({col: colour[(r + b) * W + c + a] || [0, 0, 0],
                                   S: scaled(rows[r + b].L[c], rows[r + b].g[c + a]),
                                   T: scaled(cols[c + a].L[r], cols[c + a].g[r + b])});
        mesh.colours.push([[corner(0, 0), corner(0, 1)], [corner(1, 0), corner(1, 1)]]);
      }
  }

  // ---- Tessellation ------------------------------------------------------------------------

  // The 4×4 control net q[a][b] (a along s) of patch (c, r) through the affine transform m.
  function controlNet(mesh, c, r, m) {
    const {C, P, H, V} = mesh, W = C + 1, t = mesh.tensor[r * C + c];
    const top = H[r * C + c], bottom = H[(r + 1) * C + c], left = V[r * W + c], right = V[r * W + c + 1];
    const corners = [P[r * W + c], P[r * W + c + 1], P[(r + 1) * W + c + 1], P[(r + 1) * W + c]];
    const q = [[corners[0], left[0], left[1], corners[3]], [top[0], , , bottom[0]],
               [top[1], , , bottom[1]], [corners[1], right[0], right[1], corners[2]]];
    // Interior points next to corners 00, 30, 33, 03, as `tensor` lists them.
    [[1, 1], [2, 1], [2, 2], [1, 2]].forEach(([a, b], k) => {
      q[a][b] = t.length > 7 ? [corners[k][0] + t[2 * k], corners[k][1] + t[2 * k + 1]] :
        coonsInterior(q, a > 1, b > 1);
    });
    return q.map((column) => column.map((p) => apply(m, p)));
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

  // Cells along s (along = 0) or t (1) that keep a patch's triangles within the tolerances:
  // for the position from the control net's second differences and twists (device px), for
  // the colour from the Hermite data (basis second derivatives are at most 6 for values, 4
  // for slopes), but no smaller than SMALLEST_CELL for the colour's sake.
  function cellsFor(mesh, q, colours, along) {
    const at = (i, j) => along ? q[j][i] : q[i][j];
    let bend = 0, twist = 0, length = 0, colour = 0;
    for (let j = 0; j < 4; j++)
      for (let i = 0; i < 3; i++) {
        const p = at(i, j), n = at(i + 1, j);
        length = max(length, 3 * hypot(n[0] - p[0], n[1] - p[1]));
        if (i < 2) bend = max(bend, hypot(at(i + 2, j)[0] - 2 * n[0] + p[0], at(i + 2, j)[1] - 2 * n[1] + p[1]));
        if (j < 3) twist = max(twist, hypot(at(i + 1, j + 1)[0] - n[0] - at(i, j + 1)[0] + p[0],
                                                at(i + 1, j + 1)[1] - n[1] - at(i, j + 1)[1] + p[1]));
      }
    for (let k = 0; k < 2 && mesh.bicubic; k++)
      for (let ch = 0; ch < 3; ch++) {
        const c0 = along ? colours[k][0] : colours[0][k], c1 = along ? colours[k][1] : colours[1][k];
        const slope = (c) => abs((along ? c.T : c.S)[ch]);
        colour = max(colour, 6 * abs(c1.col[ch] - c0.col[ch]) + 4 * slope(c0) + 4 * slope(c1));
      }
    const n = max(sqrt((6 * bend + 9 * twist) / (4 * POSITION_TOLERANCE)),
                       min(sqrt(colour / (8 * COLOUR_TOLERANCE)), length / SMALLEST_CELL));
    return min(MAX_CELLS, ceil(n) || 1);
  }

  const bernstein = (u, v = 1 - u) => [v * v * v, 3 * u * v * v, 3 * u * u * v, u * u * u];
  const hermite = (u, u2 = u * u, u3 = u2 * u) => [1 - 3 * u2 + 2 * u3, 3 * u2 - 2 * u3, u - 2 * u2 + u3, u3 - u2];

  // The meshgradient as triangles through the affine transform m (device pixels): positions
  // xy, colours rgb (0–1) and vertex indices, each patch a grid of cells of its own. Where two
  // neighbours are cut differently, the chords of their shared edge part by at most twice the
  // position tolerance; the dilation fills any pixel whose centre falls between them.
  function tessellate(mesh, m) {
    let vertices = 0, cells = 0, v = 0, n = 0;
    const patches = mesh.colours.map((corners, k) => {
      const q = controlNet(mesh, k % mesh.C, floor(k / mesh.C), m);
      const ns = cellsFor(mesh, q, corners, 0), nt = cellsFor(mesh, q, corners, 1);
      vertices += (ns + 1) * (nt + 1);
      cells += ns * nt;
      return {q, corners, ns, nt};
    });
    const xy = new Float32Array(2 * vertices), rgb = new Float32Array(3 * vertices);
    const indices = new Uint32Array(6 * cells);
    for (const {q, corners, ns, nt} of patches) {
      // Bilinear colour is the Hermite form with the basis (1 − u, u) and no slopes.
      const basis = mesh.bicubic ? hermite : (u) => [1 - u, u, 0, 0], Bs = [], Hs = [];
      for (let a = 0; a <= ns; a++) {
        Bs[a] = bernstein(a / ns);
        Hs[a] = basis(a / ns);
      }
      const cell = [0, 1, ns + 2, 0, ns + 2, ns + 1];  // a cell's two triangles from its first vertex
      for (let b = 0; b <= nt; b++) {
        // The patch at this t: control points along s, and for the corner columns i = 0, 1 the
        // colour and its slope along s.
        const Bt = bernstein(b / nt), Ht = basis(b / nt);
        const points = q.map((column) => [0, 1].map((k) => Bt.reduce((sum, w, j) => sum + w * column[j][k], 0)));
        const along = (i, f) => [0, 1, 2].map((ch) => Ht[0] * f(corners[i][0], 0)[ch] + Ht[1] * f(corners[i][1], 1)[ch] +
                                                      Ht[2] * f(corners[i][0], 2)[ch] + Ht[3] * f(corners[i][1], 3)[ch]);
        const colour = [0, 1].map((i) => along(i, (c, j) => j < 2 ? c.col : c.T));
        const slope = [0, 1].map((i) => along(i, (c, j) => j < 2 ? c.S : [0, 0, 0]));
        for (let a = 0; a <= ns; a++, v++) {
          const B = Bs[a], H = Hs[a];
          for (let k = 0; k < 2; k++)
            xy[2 * v + k] = B[0] * points[0][k] + B[1] * points[1][k] + B[2] * points[2][k] + B[3] * points[3][k];
          for (let ch = 0; ch < 3; ch++)
            rgb[3 * v + ch] = H[0] * colour[0][ch] + H[1] * colour[1][ch] + H[2] * slope[0][ch] + H[3] * slope[1][ch];
          for (let k = 0; a < ns && b < nt && k < 6; k++) indices[n++] = v + cell[k];
        }
      }
    }
    return {xy, rgb, indices};
  }

  // ---- Drawing -----------------------------------------------------------------------------

  // The shared WebGL context (one for every mesh on the page) with its program, or null.
  function webgl() {
    if (gl !== undefined || (gl = null) || options.noWebGL) return gl;
    try {
      const ctx = document.createElementNS(HTML_NS, 'canvas').getContext('webgl', {antialias: false});
      const program = ctx.createProgram();
      [[ctx.VERTEX_SHADER, 'attribute vec2 p;attribute vec3 c;uniform vec2 z;varying vec3 v;' +
         'void main(){v=c;gl_Position=vec4((p/z*2.-1.)*vec2(1,-1),0,1);}'],
       [ctx.FRAGMENT_SHADER, 'precision highp float;varying vec3 v;void main(){gl_FragColor=vec4(v,1.);}']
      ].forEach(([type, source]) => {
        const shader = ctx.createShader(type);
        ctx.shaderSource(shader, source);
        ctx.compileShader(shader);
        ctx.attachShader(program, shader);
      });
      ctx.bindAttribLocation(program, 0, 'p');  // positions, then colours
      ctx.bindAttribLocation(program, 1, 'c');
      ctx.linkProgram(program);
      if (ctx.getExtension('OES_element_index_uint') && ctx.getProgramParameter(program, ctx.LINK_STATUS)) {
        ctx.useProgram(program);
        ctx.bindBuffer(ELEMENT_ARRAY_BUFFER, ctx.createBuffer());
        ctx.enableVertexAttribArray(0);
        ctx.enableVertexAttribArray(1);
        gl = {ctx, size: ctx.getUniformLocation(program, 'z')};
      }
    } catch (e) {
      gl = null;
    }
    return gl;
  }

  // Draws the triangles with WebGL into the 2D context `out` (device row 0 at the top).
  function drawWebGL({xy, rgb, indices}, out) {
    const {ctx, size} = gl, {width, height} = out.canvas;
    ctx.canvas.width = width;
    ctx.canvas.height = height;
    ctx.viewport(0, 0, width, height);
    ctx.clear(ctx.COLOR_BUFFER_BIT);
    ctx.uniform2f(size, width, height);
    ctx.bufferData(ELEMENT_ARRAY_BUFFER, indices, STREAM_DRAW);
    const buffers = [xy, rgb].map((data, k) => {
      const buffer = ctx.createBuffer();
      ctx.bindBuffer(ARRAY_BUFFER, buffer);
      ctx.bufferData(ARRAY_BUFFER, data, STREAM_DRAW);
      ctx.vertexAttribPointer(k, k + 2, ctx.FLOAT, false, 0, 0);
      return buffer;
    });
    ctx.drawElements(ctx.TRIANGLES, indices.length, ctx.UNSIGNED_INT, 0);
    buffers.forEach((b) => ctx.deleteBuffer(b));
    out.drawImage(ctx.canvas, 0, 0);  // in the same task, before the drawing buffer is cleared
  }

  // Draws the triangles into the 2D context `out` in script (the canvas 2D fallback): every pixel whose
  // centre a triangle covers (edges included) gets the colour interpolated there.
  function drawSoftware({xy, rgb, indices}, out) {
    const {width: w, height: h} = out.canvas, image = out.createImageData(w, h), pixels = image.data;
    for (let k = 0; k < indices.length; k += 3) {
      const [i0, i1, i2] = indices.subarray(k, k + 3), x0 = xy[2 * i0], y0 = xy[2 * i0 + 1];
      const dx1 = xy[2 * i1] - x0, dy1 = xy[2 * i1 + 1] - y0, dx2 = xy[2 * i2] - x0, dy2 = xy[2 * i2 + 1] - y0;
      const area = dx1 * dy2 - dx2 * dy1;
      const xs = [0, dx1, dx2].map((d) => d + x0), ys = [0, dy1, dy2].map((d) => d + y0);
      for (let y = max(0, floor(min(...ys))); area && y < min(h, max(...ys)); y++)
        for (let x = max(0, floor(min(...xs))); x < min(w, max(...xs)); x++) {
          // Barycentric weights of vertices 1 and 2 at the pixel centre.
          const px = x + 0.5 - x0, py = y + 0.5 - y0;
          const w1 = (px * dy2 - dx2 * py) / area, w2 = (dx1 * py - px * dy1) / area, w0 = 1 - w1 - w2;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const o = 4 * (y * w + x);
          for (let ch = 0; ch < 3; ch++)
            pixels[o + ch] = 255 * (w0 * rgb[3 * i0 + ch] + w1 * rgb[3 * i1 + ch] + w2 * rgb[3 * i2 + ch]);  // rounded by the array
          pixels[o + 3] = 255;
        }
    }
    out.putImageData(image, 0, 0);
  }

  // Grows the drawn pixels by DILATION pixels: a transparent pixel next to drawn ones takes
  // the colour of the first of them (sides before corners).
  function dilate(pixels, w, h) {
    const rgba = new Uint32Array(pixels.buffer);  // one pixel per element, 0 where transparent
    for (let step = 0; step < DILATION; step++) {
      const drawn = rgba.slice();
      for (let y = 0, k = 0; y < h; y++)
        for (let x = 0; x < w; x++, k++) {
          const l = x > 0, r = x < w - 1, u = y > 0, d = y < h - 1;
          if (!drawn[k])
            rgba[k] = (l && drawn[k - 1]) || (r && drawn[k + 1]) || (u && drawn[k - w]) || (d && drawn[k + w]) ||
              (l && u && drawn[k - w - 1]) || (r && u && drawn[k - w + 1]) || (l && d && drawn[k + w - 1]) ||
              (r && d && drawn[k + w + 1]);  // false stores 0
        }
    }
  }

  // ---- Shapes ------------------------------------------------------------------------------

  // The box [x0, y0, x1, y1] of the points through m.
  function box(points, m) {
    const b = [Infinity, Infinity, -Infinity, -Infinity];
    for (let p of points) {
      p = apply(m, p);
      b[0] = min(b[0], p[0]);
      b[1] = min(b[1], p[1]);
      b[2] = max(b[2], p[0]);
      b[3] = max(b[3], p[1]);
    }
    return b;
  }

  // Draws one shape's mesh at the resolution it is shown at, unless that has not changed.
  function draw(record) {
    const ctm = record.shape.getScreenCTM(), ratio = devicePixelRatio;
    if (!ctm) return;  // not rendered
    let m = [ctm.a, ctm.b, ctm.c, ctm.d, ctm.e, ctm.f].map((v) => v * ratio);
    if (m.join() == record.key) return;
    record.key = m.join();
    const mesh = record.mesh, points = [...mesh.P, ...mesh.H.flat(), ...mesh.V.flat()].filter((p) => p);
    let b = box(points, multiply(m, mesh.transform));
    const side = MAX_SIDE - 2 * DILATION - 4;
    const shrink = min(1, side / (b[2] - b[0]), side / (b[3] - b[1]),
                            sqrt(MAX_AREA / (b[2] - b[0] + 1) / (b[3] - b[1] + 1)));
    if (!(shrink > 0)) return;
    m = m.map((v) => v * shrink);
    b = b.map((v) => v * shrink);
    const x0 = floor(b[0]) - DILATION - 1, y0 = floor(b[1]) - DILATION - 1;
    const w = ceil(b[2]) + DILATION + 1 - x0, h = ceil(b[3]) + DILATION + 1 - y0;
    const triangles = tessellate(mesh, multiply([1, 0, 0, 1, -x0, -y0], multiply(m, mesh.transform)));
    const canvas = document.createElementNS(HTML_NS, 'canvas'), out = canvas.getContext('2d', {willReadFrequently: true});  // pixels kept in memory
    canvas.width = w;
    canvas.height = h;
    (webgl() ? drawWebGL : drawSoftware)(triangles, out);
    const image = out.getImageData(0, 0, w, h);
    dilate(image.data, w, h);
    out.putImageData(image, 0, 0);
    paint(record, m, [x0, y0, w, h], canvas.toDataURL());
  }

  // Paints the shape with the image: a pattern in device pixels (patternTransform maps them to
  // the shape's user space) whose one tile holds the shape's whole box, so that no second copy
  // of the image shows inside the shape.
  function paint(record, m, [x, y, w, h], url) {
    if (!record.pattern) {
      record.pattern = document.createElementNS(SVG_NS, 'pattern');
      record.image = record.pattern.appendChild(document.createElementNS(SVG_NS, 'image'));
      record.pattern.id = 'gradmesh-' + ++patternCount;
      record.gradient.before(record.pattern);
      record.shape.style.fill = `url(#${record.pattern.id})`;
    }
    const d = m[0] * m[3] - m[1] * m[2], bbox = record.shape.getBBox();
    const inverse = [m[3], -m[1], -m[2], m[0], m[2] * m[5] - m[3] * m[4], m[1] * m[4] - m[0] * m[5]].map((v) => v / d);
    const tile = box([[bbox.x, bbox.y], [bbox.x + bbox.width, bbox.y + bbox.height], [bbox.x, bbox.y + bbox.height],
                      [bbox.x + bbox.width, bbox.y]], m);
    const tx = floor(tile[0]) - 2, ty = floor(tile[1]) - 2;
    const set = (el, values) => Object.entries(values).forEach(([name, value]) => el.setAttribute(name, value));
    set(record.pattern, {patternUnits: 'userSpaceOnUse', patternTransform: `matrix(${inverse})`, x: tx, y: ty,
                         width: ceil(tile[2]) + 2 - tx, height: ceil(tile[3]) + 2 - ty});
    set(record.image, {x: x - tx, y: y - ty, width: w, height: h, href: url});  // tile-relative
  }

  // Finds the shapes painted with a meshgradient that are not drawn yet, and draws them.
  function scan() {
    const started = performance.now();
    let found = 0;
    for (const shape of document.querySelectorAll('path,rect,circle,ellipse,polygon,polyline')) {
      const id = !shape.gradmeshRecord && shape.namespaceURI == SVG_NS && paintedId(shape);
      const gradient = id && elementById(shape, id);
      if (!gradient || gradient.localName != 'meshgradient') continue;
      if (!gradient.gradmeshMesh) patchColours(gradient.gradmeshMesh = parseMesh(gradient));
      if (!gradient.gradmeshMesh.C) continue;
      records.push(shape.gradmeshRecord = {shape, gradient, mesh: gradient.gradmeshMesh});
      draw(shape.gradmeshRecord);
      found++;
    }
    if (options.timing && found)
      console.log(`gradmesh ${found} meshes ${performance.now() - started} ms ${gl ? 'webgl' : '2d'}`);
  }

  // Draws again every mesh whose transform to the screen has changed (zoom, resize).
  const redraw = () => records.forEach(draw);

  window.gradmeshMeshes = {scan, redraw, get mode() { return webgl() ? 'webgl' : '2d'; }};
  let pending = 0;
  addEventListener('resize', () => pending || (pending = requestAnimationFrame(() => redraw(pending = 0))));
  if (document.readyState == 'loading') document.addEventListener('DOMContentLoaded', scan);
  scan();
})();
