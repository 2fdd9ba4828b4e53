// Every command of `gradmesh`, in one list: its name and its help. Both programs answer
// --help, --version and `<command> --help` from here; gradmesh_main.cpp says which commands
// run in the launcher and imaging_commands.cpp runs every command.
#include "commands.h"

#include <cstdio>
#include <cstring>

#include "meshcore/printable_text.h"

namespace gm::cli {

namespace {

// What every command takes besides its own options (verbosity.h), at the end of each help.
#define GRADMESH_COMMON_OPTIONS                                                                   \
    "  -q, --quiet             print nothing but errors on standard error\n"                     \
    "  --verbose               also each stage's seconds and the figures on standard error\n"    \
    "  -h, --help              this help\n"

const char* const kMainHelp =
    "gradmesh — raster images to topology-preserving gradient meshes\n"
    "\n"
    "usage: gradmesh <command> [options]\n"
    "\n"
    "commands:\n"
    "  convert IN -o OUT     convert an image (.png .jpg ...) or a mesh file to .gmb .svg .eps .pdf .png\n"
    "  render IN -o OUT.png  re-render a mesh file as a raster image\n"
    "  info IN               meshes, grid sizes, holes, patches, bytes\n"
    "  view IN -o PAGE.html  a page to look at a mesh file: render, mesh lines, zoom, figures\n"
    "  compare A B           error figures between two images (E, RMSE, PSNR, max, coverage)\n"
    "  sample OUT.gmb        write the built-in sample document (a mesh with 3 holes + a curved mesh)\n"
    "  batch INPUTS --output-dir DIR  many images (directories, globs, manifests), resumable\n"
    "\n"
    "`gradmesh <command> --help` describes each command. A file name `-` is standard input\n"
    "(an image or a mesh file, by content) or, after -o, standard output (with --to FORMAT).\n"
    "\n"
    "options of every command:\n" GRADMESH_COMMON_OPTIONS
    "  --version               the version\n"
    "\n"
    "On a terminal, a run that lasts over a second shows its progress on standard error.\n";

// convert: the options of every input, then those of raster inputs.
const char* const kConvertHelp =
    "usage: gradmesh convert IN -o OUT [options]\n"
    "       gradmesh convert IN... --output-dir DIR [--to FORMAT] [options]\n"
    "  Reads IN (by content and extension; - reads standard input) and writes OUT in the\n"
    "  format of its extension, or of --to.\n"
    "  -o, --output PATH       output file (never the input); - writes standard output\n"
    "  --to FORMAT             the output's format where its name does not say it (-o -, a\n"
    "                          name without extension): gmb, svg, svgz, eps, pdf, png, jpg,\n"
    "                          tif, exr\n"
    "  --output-dir DIR        several inputs: each to DIR/<stem>.<ext> (--to, default gmb);\n"
    "                          one that fails does not stop the others (exit 1 at the end)\n"
    "  --compact               .gmb: quantised, compressed (positions within 1/64 px)\n"
    "  --compact-level L       .gmb: compact on coarser grids, L = 0 (as --compact) to 6, or\n"
    "                          auto (image inputs): the coarsest level whose file adds at most\n"
    "                          5% to the mesh's E; 2 is ~40% smaller for ~0.2 dB on a photo.\n"
    "                          From an image, colours are refitted to the file's grids\n"
    "  --legacy                write every mesh with holes as its hole-free pieces\n"
    "  --svg-colors MODE       SVG: bicubic (default: one patch per patch, type=bicubic, as\n"
    "                          Inkscape draws it; Hermite meshes are refitted to it and the\n"
    "                          error printed) or exact (Hermite colours kept by subdividing\n"
    "                          patches; large). OUT.svgz writes it gzipped\n"
    "  --svg-script MODE       SVG: embed (default: a script that draws the meshes in web\n"
    "                          browsers, which have no mesh support; docs/browsers.md) or none\n"
    "  --color-tolerance T     exact-colour subdivision tolerance, 0-255 units (default 1)\n"
    "  --min-piece PX          exact colours: sub-patches at least PX canvas pixels long\n"
    "                          (default 1; 0: split until within the tolerance, however small)\n"
    "  --svg-fallback KIND     SVG: our render beneath the meshes, for viewers that draw no\n"
    "                          meshes (browsers' <img>, CSS, librsvg): png (every viewer),\n"
    "                          webp (lossless, smaller; browsers only, not librsvg) or none\n"
    "                          (default). Not updated when the mesh is edited in Inkscape\n"
    "  --text-shading          EPS/PDF: text DataSource instead of the binary stream\n"
    "  --scale S               raster outputs: pixels per canvas pixel (default 1)\n"
    "  --background COLOR      raster outputs: #rrggbb, #rrggbbaa, white, black or none\n"
    "  --mesh-lines COLOR      raster outputs: draw every patch edge and node in COLOR\n"
    "  limits (docs/limits.md), checked before the work:\n"
    "  --max-memory SIZE       memory budget, e.g. 4G (default), 512M\n"
    "  --max-document-patches N  patches of all meshes read or converted (default 1048576)\n"
    "  --max-output-bytes N    SVG/EPS/PDF outputs (default 1073741824)\n"
    "  --max-canvas-pixels N   raster outputs (default 268435456 = 16384^2)\n"
    "  raster input (IN is .png .jpg .tif .exr ...): the object becomes gradient meshes\n"
    "  --mask M.png            object mask (white = object); else the alpha channel when it\n"
    "                          makes 0.1% of the pixels or more transparent (alpha < 0.5);\n"
    "                          else foreground extraction (GrabCut)\n"
    "  --max-error E           target mean error per region, 0-255 units (default 3)\n"
    "  --max-patches N         patch budget per region (default 400; with --segment 8000,\n"
    "                          and at most one patch per 8 pixels of the region)\n"
    "  --colors MODE           bicubic (default: node colours fitted, slopes by SVG's bicubic\n"
    "                          rule, so the SVG is one patch per patch exactly as Inkscape\n"
    "                          draws it; no slopes in the .gmb), hermite (free slopes: the\n"
    "                          least raster error per patch; the SVG refits them) or sampled\n"
    "                          (the paper's: node colours sampled, bicubic). fit and rule are\n"
    "                          aliases of hermite and bicubic\n"
    "  --report R.json         per-stage seconds, patches, errors, bytes, refinement sequence\n"
    "  --report R.html         the same conversion as a page to look at (gradmesh view --help)\n"
    "  --max-pixels N          refuse larger images (default 67108864 = 64 Mi pixels)\n"
    "  --min-area N            drop object components under N pixels (default 64)\n"
    "  --min-hole N            fill holes under N pixels (default 16)\n"
    "  --samples F             triangulation samples per region pixel (default 0.03,\n"
    "                          at most 40000 per region)\n"
    "  --segment               the whole image: segmented into large regions (graph-based,\n"
    "                          GrabCut-refined), one mesh per region, holes included, over a\n"
    "                          coarse base mesh so that every pixel is painted\n"
    "  --segments N            with --segment: roughly how many regions (default: automatic;\n"
    "                          a photograph, shaded and without ink outlines, about 100)\n"
    "  --min-region N          with --segment: merge regions under N pixels into a neighbour\n"
    "                          (default: scaled to the image)\n"
    "  --total-patches N       with --segment: one patch budget for the whole image, shared\n"
    "                          out where it lowers the error most (each region converted at\n"
    "                          several budgets; --max-error still stops each region);\n"
    "                          0: every region one flat colour or linear gradient, no mesh\n"
    "                          (a flat trace)\n"
    "  --no-strokes            with --segment: thin lines and rings as filled outlines, not\n"
    "                          as strokes along their centrelines\n"
    "  --no-gradients          with --segment: flat regions in one colour each, never a\n"
    "                          linear gradient\n"
    "  --no-residue            with --segment: no flat shapes on top for the details the\n"
    "                          regions miss by far (specks, highlights)\n"
    "  --threads N             regions converted at once (default: all cores)\n"
    GRADMESH_COMMON_OPTIONS;

const char* const kViewHelp =
    "usage: gradmesh view IN -o PAGE.html [--image ORIGINAL] [options]\n"
    "  Writes one self-contained HTML page (no network access) to look at a mesh file (.gmb\n"
    "  .svg .svgz): our render, the mesh lines over it, zoom to 8x with pan, and the figures\n"
    "  (patches, meshes, holes, colour model, bytes of each format). With the image the mesh\n"
    "  was converted from, also that image, an error heat map and E / PSNR. From an image,\n"
    "  `gradmesh convert IMG -o OUT --report PAGE.html` writes the same page with the\n"
    "  conversion's own figures (seconds per stage). docs/view.md describes the page.\n"
    "  -o, --output PATH       the page (.html or .htm; never the input)\n"
    "  --image ORIGINAL        the source image (.png .jpg .tif .exr), the canvas's size\n"
    "  --max-output-bytes N    the page, and each format's encoding (default 1073741824)\n"
    "  --max-memory SIZE, --max-document-patches N, --max-canvas-pixels N: as for convert\n"
    GRADMESH_COMMON_OPTIONS;

// batch (batch_command.h): convert, many times over.
const char* const kBatchHelp =
    "usage: gradmesh batch INPUTS... --output-dir DIR [--to gmb,svg] [options]\n"
    "  Converts many images as `convert` converts one (the same bytes), one image per core at\n"
    "  a time. A rerun skips the images already done and redoes the others (docs/batch.md).\n"
    "  INPUTS                  directories (their images), glob patterns ('photos/*.jpg'),\n"
    "                          image files, manifests (.csv or .jsonl: image, mask, options,\n"
    "                          output per line)\n"
    "  --output-dir DIR        where DIR/<stem>.<ext> are written (made if missing)\n"
    "  --to FORMAT[,FORMAT]    the outputs of each image: gmb (default), svg, svgz, eps, pdf,\n"
    "                          png, ... ; one conversion writes them all\n"
    "  --log FILE              the JSON-lines log, appended: one record per image (default\n"
    "                          DIR/gradmesh-batch.jsonl); a rerun reads it to resume\n"
    "  --jobs N                images converted at once (default: the cores this process may\n"
    "                          use); each conversion runs on one thread unless --threads says\n"
    "  --shard i/n             only the images k with k mod n = i (0 <= i < n), for n machines\n"
    "                          sharing a manifest\n"
    "  --force                 convert every image, done or not\n"
    "  --dry-run               print what would be converted and what skipped, convert nothing\n"
    "  Every option of convert for images (--max-error, --segment, --compact, --svg-*, limits\n"
    "  ...) applies to each image; a manifest's options add to them. Not --output, --mask\n"
    "  (per image, in a manifest) or --report.\n"
    "  Exit 0 when every image is done, 1 when one failed (its record says why).\n"
    GRADMESH_COMMON_OPTIONS;

}  // namespace

const char* mainHelp() { return kMainHelp; }

const char* versionText() { return "gradmesh 0.1.0"; }

const std::vector<Command>& commands() {
    static const std::vector<Command> list = {
        {"convert", kConvertHelp},
        {"render",
         "usage: gradmesh render IN -o OUT.png [--scale S] [--background COLOR] [--mesh-lines COLOR]\n"
         "       gradmesh render IN... --output-dir DIR [--to FORMAT] [options]\n"
         "  Re-renders the meshes of IN (exact Ferguson evaluation, anti-aliased outline); IN\n"
         "  - reads a mesh file (.gmb, SVG) from standard input.\n"
         "  -o, --output PATH       .png .jpg .tif .exr; - writes standard output (with --to)\n"
         "  --to FORMAT             png, jpg, tif or exr, where the output's name does not say\n"
         "  --output-dir DIR        several inputs: each to DIR/<stem>.<ext> (--to, default png)\n"
         "  --scale S               output pixels per canvas pixel (default 1)\n"
         "  --background COLOR      #rrggbb, #rrggbbaa, white, black or none (default none)\n"
         "  --mesh-lines COLOR      draw every patch edge (grid lines, outline, slits) and node in\n"
         "                          COLOR over the render, as a mesh tool shows them\n"
         "  --max-memory SIZE, --max-document-patches N, --max-canvas-pixels N: as for convert\n"
         GRADMESH_COMMON_OPTIONS},
        {"info",
         "usage: gradmesh info IN\n"
         "  Prints the canvas, and per mesh its grid, patches, holes and legacy piece count.\n"
         "  IN - reads the mesh file from standard input.\n"
         GRADMESH_COMMON_OPTIONS},
        {"compare",
         "usage: gradmesh compare A B [--mask M] [--background COLOR] [--erode N]\n"
         "  Error of image B against image A over the pixels where the mask is white (default:\n"
         "  where A is opaque), in 0-255 units: E (mean absolute error per channel), RMSE, PSNR,\n"
         "  max, the 99th percentile of the channel errors, and the fraction of those pixels that\n"
         "  B leaves uncovered.\n"
         "  --mask M            compare where the image M is white\n"
         "  --background COLOR  composite both images over this opaque colour first: B's partly\n"
         "                      transparent pixels (seams between meshes) then count as the\n"
         "                      background shows through them\n"
         "  --erode N           leave out pixels within N px of the compared area's edge\n"
         GRADMESH_COMMON_OPTIONS},
        {"view", kViewHelp},
        {"batch", kBatchHelp},
        {"sample",
         "usage: gradmesh sample OUT\n"
         "  Writes the built-in sample document (512x512: a mesh with 3 holes and a curved mesh)\n"
         "  in the format of OUT's extension.\n"
         GRADMESH_COMMON_OPTIONS},
    };
    return list;
}

const Command* findCommand(const std::string& name) {
    for (const Command& c : commands())
        if (name == c.name) return &c;
    return nullptr;
}

std::optional<int> answerWithoutRunning(int argc, char** argv) {
    if (argc < 2) {
        std::fputs(kMainHelp, stderr);
        return 2;
    }
    const std::string name = argv[1];
    if (name == "--help" || name == "-h" || name == "help") {
        std::fputs(kMainHelp, stdout);
        return 0;
    }
    if (name == "--version") {
        std::puts(versionText());
        return 0;
    }
    const Command* command = findCommand(name);
    if (!command) {
        std::fprintf(stderr, "gradmesh: unknown command '%s' (try gradmesh --help)\n",
                     printableText(name).c_str());
        return 2;
    }
    for (int k = 2; k < argc; ++k) {
        if (std::strcmp(argv[k], "--help") == 0 || std::strcmp(argv[k], "-h") == 0) {
            std::fputs(command->help, stdout);
            return 0;
        }
    }
    return std::nullopt;
}

}  // namespace gm::cli
