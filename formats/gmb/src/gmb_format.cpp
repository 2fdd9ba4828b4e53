// .gmb — the native binary format of gradmesh, versions 1.4 and 2.0. This comment is the
// specification. Version 2.0 is 1.4 in shorter framing (see "Version 2" below); the writer
// writes compact files as 2.0 and lossless files as 1.0.
//
// Conventions. Integers are little-endian and fixed-width unless called varint. f64 is an
// IEEE 754 binary64 stored as its 8 bytes, little-endian. varint: unsigned LEB128, at most 10
// bytes. svarint: a varint holding the zigzag code (n << 1) ^ (n >> 63) of a signed 64-bit n.
// Arithmetic on quantised values is on exact integers unless said otherwise; floor is towards
// minus infinity.
//
// File = header, sections, and nothing after the END section.
//
// Header, 12 bytes
//    0   8  magic 89 47 4D 42 0D 0A 1A 0A ("\x89GMB\r\n\x1a\n")
//    8   2  major version, 1 (or 2: see "Version 2"). A reader refuses a major it does not
//           know.
//   10   2  minor version: 4 if the file has a CMS3 section, else 3 if it has a CMS2 section
//           (only 1.3 writers wrote those), else 2 if it has a CMSH section (1.2 writers), else
//           1 if some MESH section says encoding 2, else 0
//           (a writer marks the lowest version that holds the file, so lossless files remain
//           1.0 files). A newer minor may add optional sections, append fields to the DOCU and
//           MESH payloads (a reader of an older minor skips both), add mesh encodings (an older
//           reader refuses a mesh in an encoding it does not know: 1.0 readers refuse encoding
//           2) and add required sections (an older reader refuses the file: 1.1 readers refuse
//           CMSH, 1.2 readers CMS2, 1.3 readers CMS3, as unknown required sections).
//
// Section, 28 + S bytes
//    0   4  tag, four ASCII characters
//    4   1  flags: bit 0 = optional (a reader that does not know the tag skips the section;
//           a required section it does not know is an error). Other bits are 0 in 1.x and
//           ignored by a 1.x reader.
//    5   1  codec of the payload: 0 stored, 1 deflate (zlib stream, RFC 1950), 2 zstd frame(s)
//    6   2  reserved, 0
//    8   8  S: payload bytes stored in the file
//   16   8  N: payload bytes after decompression (N = S when stored)
//   24   S  payload
//  24+S  4  CRC-32 (zlib's crc32) of the section's bytes 0 .. 24+S-1
//
// Section order (unknown optional sections may stand between any two):
//   DOCU                  once, first
//   the meshes, in painting order, each either in its own sections:
//     MESH KNOT NODE      always
//     SLIT                if and only if the mesh has slits
//     TANG                if and only if the mesh has corner tangent breaks
//   or in a CMSH section (since 1.2), a CMS2 section (since 1.3) or a CMS3 section (since 1.4),
//   each of which holds a run of one or more consecutive meshes in encoding 2; a file may mix
//   them (a writer's compact mode writes each run as CMS2 or CMS3, whichever is smaller, and
//   float64 MESH sections for meshes it cannot quantise)
//   END                   once, last, empty payload
// Every section defined by 1.x is required (flags bit 0 clear).
//
// DOCU payload, 12 bytes: u32 canvas width, u32 canvas height (pixels), u32 mesh count.
//
// Version 2 (2.0): the sections, payloads and rules of 1.4, in shorter framing; made for small
// files, where 1.x's fixed 24-byte section headers were 10 % of a 1 KB whole image. Everything
// not stated here is as in 1.4 (a 2.x file may hold every section a 1.4 file may).
//   Header: as above, major 2, minor 0. A newer 2.x minor may add what a newer 1.x minor may
//   (optional sections, appended DOCU and MESH fields, encodings, required sections).
//   Section, 11 + S bytes at least:
//      tag (4), u8 flags, u8 codec: as in 1.x
//      varint S: payload bytes stored in the file
//      varint N: payload bytes after decompression; present only when codec != 0 (N = S when
//        stored)
//      S payload bytes
//      u32 CRC-32 of the section's bytes from the tag to the end of the payload
//   DOCU payload: varint canvas width, varint canvas height, varint mesh count (then whatever
//     a later 2.x minor appends).
//   A 1.x reader refuses a 2.x file by its major; a 2.x file framed as 1.x fails the CRC of
//   its first section.
// MESH payload, 32 bytes: u32 C (patch columns), u32 R (patch rows), u32 slit count,
//   u32 corner tangent break count, u8 encoding (0 float64 = lossless, 1 quantised (1.0),
//   2 quantised and range-coded (since 1.1; the writer's compact mode writes such meshes as
//   CMSH records since 1.2 and in CMS2 sections since 1.3 instead)), u8 flags (bit 0: colour derivatives omitted; the reader
//   recomputes them with applyColorRule from the decoded mesh; bit 1: the mesh is in the
//   Bicubic colour model (meshcore/bicubic_colors.h) — a coded mesh then stores no colour
//   derivatives, a float64 mesh stores them as zeros, and the reader ignores them; other bits
//   0, ignored in a float64 MESH), 7 × i16 exponents e for the quantised fields knot, pos, posU, posV, col, colU,
//   colV (0 for float64), each within ±960. Encodings 1 and 2: a quantised knot, position or colour q of field f stands for
//   q · 2^e_f; derivatives differ (below).
//
// A node record has 15 components: pos.x pos.y posU.x posU.y posV.x posV.y col.r col.g col.b
// colU.r colU.g colU.b colV.r colV.g colV.b; the last six are absent when colour derivatives are
// omitted. Slit-end tangents and corner tangent breaks use the posU and colU fields.
//
// Float64 encoding (every value an f64)
//   KNOT  u_0 .. u_C, then v_0 .. v_R
//   NODE  (C+1)(R+1) node records, row-major (index j(C+1)+i)
//   SLIT  per slit: u32 row, u32 i0, u32 i1; left end posU.x posU.y [colU.r colU.g colU.b];
//         right end likewise; then i1-i0-1 node records: the copies used below the row of
//         columns i0+1 .. i1-1. The end colU is absent when colour derivatives are omitted.
//   TANG  per break: u32 i, u32 j (the patch), u8 a, u8 b (its corner), posU.x posU.y
//         [colU.r colU.g colU.b], the colU absent when colour derivatives are omitted
//
// Quantised encoding, 1 (every value q an svarint unless said otherwise; |q| <= 2^53).
// A derivative q of field f stands for q · 2^e_f.
//   KNOT  q(u_0), then C varints q(u_i) - q(u_{i-1}), each >= 1; then the same for v
//   NODE  one plane per node-record component, in record order; a plane holds (C+1)(R+1)
//         residuals q(i,j) - p(i,j), row-major, with the parallelogram prediction
//         p = q(i-1,j) + q(i,j-1) - q(i-1,j-1); on row 0 p = q(i-1,0), in column 0
//         p = q(0,j-1), and p(0,0) = 0
//   SLIT  per slit: varints row, i0, i1; the two end tangents as for float64 but as q values;
//         then the below copies as node records of residuals q(below) - q(node above the row in
//         the same column)
//   TANG  per break: varints i, j, u8 (a | b << 1), then posU.x posU.y [colU.rgb]
//
// Quantised and range-coded encoding, 2. KNOT, SLIT and TANG are laid out as in encoding 1;
// derivatives are scaled per node and NODE is predicted and range-coded.
//   Spans. With k_0 .. k_C the quantised u knots (the integers of KNOT), the span of column i
//   is D_i = max(k_i - k_{i-1}, k_{i+1} - k_i) + 2 over the differences that exist (in knot
//   quanta; the 2 covers the knots' own rounding); the span of row j likewise from the v knots.
//   A quantised derivative q of field f (posU, posV, colU or colV) in column i (u fields) or
//   row j (v fields) stands for ldexp(q, e_f - e_knot) / D, one binary64 division rounded to
//   nearest even (e_f is the exponent of derivative × span). The column and row are the
//   node's for node records in NODE and SLIT (a below copy is in the column and row of the
//   node above it), i0 or i1 for the left or right slit-end tangent, i + a for a tangent
//   break. Readers require |e_f - e_knot| <= 960 and |e_f - e_v| <= 16 for the four
//   derivative fields, where e_v is e_pos for posU and posV and e_col for colU and colV.
//   NODE  plane weights, then a range-coded stream that ends with the payload.
//     Planes, in coding order, with their node-record component numbers:
//       pos.x 0, pos.y 1, col.g 7, col.r 6, col.b 8, posU.x 2, posU.y 3, posV.x 4, posV.y 5,
//       colU.g 10, colU.r 9, colU.b 11, colV.g 13, colV.r 12, colV.b 14
//     (the last six absent when colour derivatives are omitted). The first five are value
//     planes; the others are derivative planes, along u (posU, colU) or v (posV, colV), of the
//     value plane of the same quantity and coordinate (posU.y and posV.y: pos.y; colU.r: col.r).
//     Siblings: pos.x of pos.y; col.g of col.r and col.b; posU.x of posU.y; posV.x of posV.y;
//     colU.g of colU.r and colU.b; colV.g of colV.r and colV.b. Other planes have none.
//     Weights: per plane in coding order, svarints a, b, s for a value plane, a, s for a
//     derivative plane; each within ±32768 (units of 1/256).
//     A plane's q(i,j) are coded row-major as residuals r(i,j) = q(i,j) - p(i,j), where
//     S = r(i,j) of the sibling plane (0 without one), and rnd(n) = floor((n + 128) / 256):
//       value plane, i > 0 and j > 0, with L = q(i-1,j), U = q(i,j-1), G = q(i-1,j-1):
//         p = L + rnd(a(U - L) + b(G - L) + sS)
//       value plane, row 0: p = q(i-1,0) + rnd(sS); column 0: p = q(0,j-1) + rnd(sS); at
//         (0,0): p = rnd(sS)
//       derivative plane along u, of field f and of value plane V of field h: with
//         i0 = max(i-1, 0), i1 = min(i+1, C), t = e_h - e_f,
//         M = (V(i1,j) - V(i0,j)) · D_i · 2^max(t,0),  W = (k_i1 - k_i0) · 2^max(-t,0),
//         c = floor((2M + W) / (2W)) clamped to ±2^62, and p = rnd(a·c + sS)
//       derivative plane along v: the same along column i with rows j0, j1, the v knots, D_j
//     then p is clamped to ±2^62 (the terms stay within 128 bits). Every q must satisfy
//     |q| <= 2^53, and every residual is then within 64 bits.
//     Residuals. Each plane has its own models (below), fresh in every NODE section (and in
//     every CMSH mesh record; CMS2 keeps them across its meshes, see there):
//     zero[16], sign[16], length[16][24], top[64]. For r(i,j), with |x| capped at 2^40 and
//     terms for residuals outside the grid 0, the context is x = min(bit length of z, 15) of
//       z = 2|r(i-1,j)| + 2|r(i,j-1)| + |r(i-1,j-1)| + |r(i+1,j-1)| + |r(i-2,j)| + 3|S|
//     (the bit length of 0 is 0). Then, as binary decisions: r != 0 with zero[x]; if so, r < 0
//     with sign[x]; with n = (bit length of |r|) - 1: n decisions 1 and then a decision 0
//     (left out when n = 63), the k-th of them (k = 0, 1, ...) with length[x][min(k, 23)];
//     if n >= 1, the bit of |r| below its leading 1 with top[n], then its n - 1 lower bits,
//     most significant first, as direct bits.
//     Models. A model holds two 16-bit estimates A and B, both 32768 at first, and a count c,
//     0 at first. It codes 1 with probability P = clamp(floor((A + B) / 2), 32, 65504) / 2^16.
//     After each decision x: if c < 30, w = 1 + floor(c / 2) and c increases by 1, else
//     w = 16; with a = min(4, w) and b = min(7, w): if x = 1, A += floor((65536 - A) / 2^a)
//     and B += floor((65536 - B) / 2^b), else A -= floor(A / 2^a) and B -= floor(B / 2^b).
//     Range coding. The decoder keeps unsigned 32-bit R and V: R = 2^32 - 1 and V = the
//     stream's bytes 1 .. 4 read big-endian (byte 0 must be 0). A decision with probability P
//     (of a 1, P in units of 2^-16): T = floor(R / 2^16) · P; if V < T it is 1 and R = T, else
//     it is 0, V -= T and R -= T. A direct bit: R = floor(R / 2); if V >= R it is 1 and
//     V -= R, else 0. After either, while R < 2^24: R = R · 2^8, V = (V · 2^8 + the next
//     byte) mod 2^32. The stream must hold exactly the bytes the decoder reads. (The encoder
//     is LZMA's: a 33-bit low end with carry propagation and five flushing bytes.) The stream
//     is therefore self-delimiting: it is 5 bytes plus one per renormalisation step.
//
// Compact meshes, CMSH (since 1.2): a run of M consecutive meshes in encoding 2 in one section,
// instead of each mesh's MESH, KNOT, NODE, SLIT and TANG sections; the data of each mesh is
// that of those sections (quantisation, spans, prediction, range coding: all as above) but for
// shorter headers and plane weights with defaults. The section is always stored (codec 0): a
// reader refuses other codecs, and a CMSH section in a file whose minor version is below 2.
//   Payload
//     varint M, the meshes in the run: at least 1, at most those DOCU declares that are not
//       yet read
//     6 svarints: the exponents e_pos, e_posU, e_posV, e_col, e_colU, e_colV of every mesh of
//       the run, each within ±960
//     M mesh records, back to back; nothing after the last
//   Mesh record
//     varints C, R, slit count, corner tangent break count: as in MESH
//     u8 flags: bit 0 = colour derivatives omitted, as in MESH; bit 1 = Bicubic colour model
//       (colour derivatives omitted too); the other bits must be 0
//     svarint e_knot, within ±960; with the shared exponents it must satisfy encoding 2's
//       rules (|e_f - e_knot| <= 960, |e_f - e_v| <= 16)
//     the knots, laid out as KNOT of encodings 1 and 2
//     the nodes: the plane weights (below), then the range-coded stream of NODE, encoding 2;
//       the stream is exactly the bytes its decoder reads, and the record goes on after them
//     the slits, laid out as SLIT of encoding 2 (nothing without slits)
//     the corner tangent breaks, laid out as TANG of encoding 2 (nothing without breaks)
//   Plane weights. A varint W: bit o (o = 0 .. F-1) stands for the o-th plane in coding order,
//   with F = 15 planes, or 9 when colour derivatives are omitted; W < 2^F. Then, in coding
//   order, for each plane whose bit is set, svarints da, db, ds (value plane) or da, ds
//   (derivative plane): its weights are the default weights plus these, and each must be within
//   ±32768. A plane whose bit is clear has the default weights:
//       pos.x, pos.y                           a = 256, b = -256, s = 0
//       col.g                                  a = 128, b = 0,    s = 0
//       col.r, col.b                           a = 128, b = 0,    s = 240
//       posU.x, posU.y, posV.x, posV.y         a = 256,           s = 0
//       colU.g, colV.g                         a = 192,           s = 0
//       colU.r, colU.b, colV.r, colV.b         a = 224,           s = 240
//
// Compact meshes in one stream, CMS2 (since 1.3; the writer's compact mode writes these instead
// of CMSH): a run of M consecutive meshes in encoding 2 in one section, all of it but M and the
// shared exponents in one range-coded stream whose models learn from mesh to mesh. The meshes'
// quantisation, spans, prediction, contexts and residual binarisation are those of encoding 2,
// and their plane weights those of CMSH (defaults, or stated differences from them); only the
// layout and the life of the models differ. The section is always stored (codec 0): a reader
// refuses other codecs, and a CMS2 section in a file whose minor version is below 3.
//   Payload
//     varint M, the meshes in the run: at least 1, at most those DOCU declares that are not
//       yet read
//     6 svarints: e_pos, e_posU, e_posV, e_col, e_colU, e_colV of every mesh of the run, each
//       within ±960 (as in CMSH)
//     one range-coded stream (the coder, decisions, direct bits and models of encoding 2) that
//       ends exactly where the payload ends: the payload holds the bytes its decoder reads and
//       nothing after them
//   Stream integers. Outside the node planes the stream holds integers, each of one of the kinds
//   below; each kind has its own models zero, sign, length[24], top[64] (no contexts). An
//   unsigned integer x: the decision x != 0 with zero; if so, x as a magnitude. A signed
//   integer x: x != 0 with zero; if so, x < 0 with sign, then |x| as a magnitude, which must be
//   below 2^63. A magnitude m >= 1, with n = (bit length of m) - 1: n decisions 1 and then a
//   decision 0 (left out when n = 63), the k-th of them (k = 0, 1, ...) with length[min(k, 23)];
//   if n >= 1, the bit of m below its leading 1 with top[n], then its n - 1 lower bits, most
//   significant first, as direct bits. (A residual's binarisation, with a single context.)
//   The 12 kinds and what they code:
//     Size          C, R                          Count         slit count, break count
//     Flags         mesh flags                    KnotExponent  e_knot (signed)
//     KnotStart     q(u_0), q(v_0) (signed)       KnotStep      knot difference - 1
//     WeightDelta   stated weight - default (s.)  SlitIndex     row, i0, i1
//     SlitEnd       slit-end tangents (signed)    SlitBelow     below-copy residuals (signed)
//     TangentIndex  i, j, a | b << 1              TangentValue  break tangents (signed)
//   Models. At the start of every CMS2 section every model of its stream is fresh (A = B =
//   32768, c = 0): the 12 kinds' models; 15 weights models weighted[0..14], one per position
//   in the coding order of the planes; 15 sets of residual models zero[16], sign[16],
//   length[16][24], top[64], one per node-record component. None is reset within the section:
//   each mesh begins with the models as the meshes before it left them. A mesh whose colour
//   derivatives are omitted (F = 9) uses only weighted[0..8] and the residual models of its nine
//   planes (components 0 to 8); the others keep their state for later meshes.
//   Each mesh, in the stream, in order:
//     C, R (Size), the slit count and the corner tangent break count (Count), unsigned; the
//       counts as in MESH
//     flags (Flags), unsigned: bit 0 = colour derivatives omitted, as in MESH; bit 1 = Bicubic
//       colour model (colour derivatives omitted too); must be 0 to 3
//     e_knot (KnotExponent), signed, within ±960; with the shared exponents it must satisfy
//       encoding 2's rules (|e_f - e_knot| <= 960, |e_f - e_v| <= 16)
//     the knots: q(u_0) (KnotStart, signed), then for i = 1 .. C, q(u_i) - q(u_{i-1}) - 1
//       (KnotStep, unsigned: the knots increase strictly); then the v knots likewise, R steps.
//       Every q(u_i) and q(v_j) is within ±2^53.
//     the plane weights: for each plane in coding order (o = 0 .. F-1), a decision with
//       weighted[o], 1 if the plane states its weights; if so, then da, db (value planes only)
//       and ds (WeightDelta, signed): its weights are CMSH's default weights plus these, each
//       within ±32768. A plane that does not state its weights has the default weights.
//     the node planes: in coding order, each plane's residuals r(i,j), row-major, with the
//       prediction and the contexts of encoding 2 (within this mesh), each coded as in NODE
//       with the residual models of the plane's node-record component
//     per slit: row, i0, i1 (SlitIndex, unsigned); the left end's posU.x posU.y [colU.r colU.g
//       colU.b], then the right end's, each a q (SlitEnd, signed; colU absent when colour
//       derivatives are omitted); then the i1 - i0 - 1 below copies, each the F components of a
//       node record in record order as q(below) - q(node above the row in the same column)
//       (SlitBelow, signed): the values of encoding 2's SLIT
//     per corner tangent break: i, j, a | b << 1 (TangentIndex, unsigned; the last at most 3);
//       then posU.x posU.y [colU.r colU.g colU.b] (TangentValue, signed): encoding 2's TANG
//   A writer may choose any weights; the stream decodes to the same values whatever it chose.
//
// Compact meshes in one stream, CMS3 (since 1.4; the writer's compact mode writes a run as CMS3
// when that is smaller than CMS2): a CMS2 section in every respect (payload, stream, meshes,
// refusals) but for the residual models of its node planes, which are fewer and start from
// priors. Files of converted images whose models have little to learn from gain most (HappyFish
// whole at 10 patches a region, level 6: 5 % smaller than CMS2; fruits whole at the default
// E 3, 0.2 %); meshes unlike converted images can be larger in CMS3. A reader refuses a CMS3
// section in a file whose minor version is below 4.
//   Residual models. 7 sets of zero[16], sign[16], length[16][24], top[64], each shared by the
//   planes of one group (node-record components):
//     P0 pos.x (0)                       P1 pos.y (1)
//     P2 posU.x, posU.y, posV.x, posV.y (2-5)
//     P3 col.r, col.b (6, 8)             P4 col.g (7)
//     P5 colU.r, colU.b, colV.r, colV.b (9, 11, 12, 14)
//     P6 colU.g, colV.g (10, 13)
//   A residual is coded as in CMS2 (its context from the residuals of its own plane and its
//   sibling's), with the models of its plane's group; so the planes of a group, in coding order,
//   learn for each other as well as from mesh to mesh.
//   Priors. At the start of the section, sign and top models are fresh (A = B = 32768, c = 0),
//   and every zero[x] and length[x][k] model of set Pg starts with c = 4 and A = B = 16 · T,
//   where T is zero[x] or length[d] of Pg below, d = min(max(x - k, 0), 9) (units of 2^-12;
//   the rates of those decisions on typical files):
//     P0 zero   2884 1640 2116 2487 3169 3578 3713 3740 3858 3925 3925 3925 4020 4020 4020 4020
//        length 3292 1509 1627 1961 2525 3097 3434 3599 3812 3947
//     P1 zero   2155 1451 1770 1958 2597 3363 3543 3677 3762 3762 3762 3762 3762 3762 3762 3762
//        length 2904 1912 1912 1912 2236 2843 3326 3595 3788 3891
//     P2 zero    776 1010 1724 2355 3044 3450 3635 3766 3919 4000 4000 4000 4000 4000 4000 4000
//        length 2024 1191 1285 1721 2401 3066 3489 3754 3908 3941
//     P3 zero     85  535  710 1806 2299 2965 3380 3416 3416 3416 3416 3416 3416 3416 3416 3416
//        length 1197  601  735  807 1407 2310 2836 3439 3789 3893
//     P4 zero   1852 1664 2765 2873 3321 3524 3736 3802 3982 3982 3982 3982 3982 3982 3982 3982
//        length 2665 1319 1353 1775 2541 3163 3532 3775 3905 3993
//     P5 zero    191  593  894 1621 2223 2660 2910 3120 3296 3521 3521 3521 3521 3521 3521 3521
//        length  379  333  418  655 1361 2176 2992 3542 3799 3941
//     P6 zero   1054 1290 1948 2456 3056 3450 3718 3882 3882 3959 4036 4036 4036 4036 4036 4036
//        length 1525 1057 1299 1744 2395 3052 3480 3780 3912 4046
//   The stream integers' models and weighted[0..14] are fresh, as in CMS2.
//
// Reading limits. Every count is checked against ReadLimits and against the bytes that remain
// before anything is allocated. A section's declared N must fit its counts, and the sum of the
// N of all sections may not exceed ReadLimits::maxFileBytes, a NODE in encoding 1 or 2
// counting max(N, 8 · values) (each value becomes an 8-byte binary64; a range-coded one decodes
// from a fraction of a bit): a decoded document is never larger than the largest file the
// caller accepts, whatever the compression ratio. A CMSH section counts its N and, for each
// mesh record, 8 · F·(C+1)(R+1) bytes for its values as well, charged as soon as the record's
// header is read. A record's counts are checked against ReadLimits and against the
// bytes that remain of the payload (at least one per knot, 6 for the weights mask and the
// stream, 3 + 2·(2 or 5) per slit, 3 + (2 or 5) per tangent break) before its knots, nodes,
// slits and breaks are read, and M against the payload's remaining bytes at 16 per record.
// A range-coded stream of V values is more than 4 + V/11730 bytes long (every decision narrows
// R to at most 1 - 31/2^16 of itself, and R >= 2^24 at the end): a reader refuses nodes whose
// remaining bytes are fewer than V/16384 before allocating their planes.
// A CMS2 or CMS3 section counts its N and, for each mesh, 8 bytes for each value it decodes to,
// charged as soon as the mesh's counts, flags and e_knot are decoded: F·(C+1)(R+1) node values,
// 3 + 2E per slit and 3 + E per corner tangent break (E = 2 values per tangent when colour
// derivatives are omitted, else 5); and F per below copy of a slit, charged once the slit's
// i0 and i1 are decoded. The counts are checked against ReadLimits as in MESH. Each value in the
// stream takes at least one decision, so where fewer than V/16384 bytes of the payload are
// still unread by the stream's decoder, a reader refuses, before allocating them, the knots
// (V = C + R + 2), the node planes (V = F·(C+1)(R+1)), the slits (V = slits · (3 + 2E)), a slit's
// below copies (V = F·(i1 - i0 - 1)) and the corner tangent breaks (V = breaks · (3 + E)).
// A mesh of a CMS2 or CMS3 stream takes at least 57 decisions (C, R 2 each; the two counts, the flags,
// e_knot, two knot starts and at least two steps 1 each; 9 weights decisions; 36 residuals), so
// M meshes need more than 4 + M/206 bytes: a reader refuses M when fewer than M/256 bytes of the
// payload remain after the exponents, and a 1.3 or 1.4 file whose DOCU declares more meshes
// than 256 times the bytes after DOCU (1.2 files: 16 bytes per mesh, the smallest CMSH record;
// 1.0 and 1.1 files: 84, the smallest MESH KNOT NODE sections).
#include <algorithm>

#include "formats/input_file.h"
#include "formats/gmb.h"
#include "gmb_pvt.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"

namespace gm {

namespace {

class GmbFormat : public MeshFormat {
public:
    std::string name() const override { return "gmb"; }
    std::vector<std::string> extensions() const override { return {".gmb"}; }
    bool canRead() const override { return true; }
    bool canWrite() const override { return true; }

    bool sniff(const std::string& head) const override {
        return head.size() >= sizeof gmb::kMagic &&
               std::equal(head.begin(), head.begin() + sizeof gmb::kMagic, gmb::kMagic);
    }

    Document read(const std::string& path, const ReadOptions& options) const override {
        const std::string bytes = readWholeFile(path, options.limits.maxFileBytes);
        return decodeGmb(bytes, options.limits, path);
    }

    std::string encode(const Document& doc, const std::string& path,
                       const WriteOptions& options) const override {
        try {
            if (!options.legacy) return encodeGmb(doc, options.compact, options.compactLevel);
            Document pieces{doc.width, doc.height, {}};
            for (const GradientMesh& m : doc.meshes)
                for (GradientMesh& piece : splitIntoLegacyMeshes(m))
                    pieces.meshes.push_back(std::move(piece));
            return encodeGmb(pieces, options.compact, options.compactLevel);
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error(e.reason(), path, e.where());
        }
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeGmbFormat() { return std::make_unique<GmbFormat>(); }

}  // namespace gm
