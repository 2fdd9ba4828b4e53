// The flat-colour tracers people use today, for bench/tracers.py: vtracer (npm
// @neplex/vectorizer) and imagetracerjs (npm imagetracerjs), installed by tracers.py in a scratch
// folder under bench-out/ (never committed).
//
//   node tracers.mjs NODE_MODULES TOOL PRESET IN.png OUT.svg
//
// TOOL is vtracer or imagetracer; PRESET one of the names below. IN must be an RGB or RGBA PNG.
import { createRequire } from 'node:module';
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';

const [modules, tool, preset, input, output] = process.argv.slice(2);
const require = createRequire(path.join(path.resolve(modules), 'x.js'));

// vtracer's own defaults (its command line's), then sparser and denser settings. The spline
// mode and stacked layers throughout, as vtracer's web demo uses them for photos.
const VTRACER = {
  default: { colorPrecision: 6, filterSpeckle: 4, layerDifference: 16 },
  detailed: { colorPrecision: 8, filterSpeckle: 2, layerDifference: 8 },
  coarse: { colorPrecision: 5, filterSpeckle: 8, layerDifference: 32 },
  photo: { colorPrecision: 8, filterSpeckle: 10, layerDifference: 48, cornerThreshold: 180 },
};

// imagetracerjs's named presets.
const IMAGETRACER = ['default', 'detailed', 'posterized2', 'smoothed'];

function vtracer(name) {
  const v = require('@neplex/vectorizer');
  const settings = VTRACER[name];
  if (!settings) throw new Error(`unknown vtracer preset ${name}`);
  return v.vectorizeSync(readFileSync(input), {
    colorMode: v.ColorMode.Color, hierarchical: v.Hierarchical.Stacked,
    mode: v.PathSimplifyMode.Spline, cornerThreshold: 60, lengthThreshold: 4,
    maxIterations: 10, spliceThreshold: 45, pathPrecision: 2, ...settings,
  });
}

function imagetracer(name) {
  if (!IMAGETRACER.includes(name)) throw new Error(`unknown imagetracer preset ${name}`);
  const root = path.join(path.resolve(modules), 'imagetracerjs');
  const ImageTracer = require(path.join(root, 'imagetracer_v1.2.6.js'));
  const PNGReader = require(path.join(root, 'nodecli', 'PNGReader.js'));
  return new Promise((resolve, reject) => {
    new PNGReader(readFileSync(input)).parse((error, png) => {
      if (error) return reject(error);
      const image = { width: png.width, height: png.height, data: png.pixels };
      resolve(ImageTracer.imagedataToSVG(image, name));
    });
  });
}

const svg = await (tool === 'vtracer' ? vtracer(preset) : imagetracer(preset));
writeFileSync(output, svg);
