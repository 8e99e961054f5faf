// Bundles the replay viewer (src/viewer.js + three.js) into dist/viewer.js,
// one minified IIFE that the C++ HTML writer inlines into every page.
// Usage: npm run build [-- OUTFILE]   (after scripts/install-viewer-deps.sh)
import { build } from 'esbuild';

// Optional output path (the CMake option FULCRUM_BUILD_VIEWER builds into the build tree).
const outfile = process.argv[2] ?? 'dist/viewer.js';

const result = await build({
  entryPoints: ['src/viewer.js'],
  bundle: true,
  minify: true,
  format: 'iife',
  target: ['es2020'],
  outfile,
  legalComments: 'eof',   // keep three.js's MIT licence notice in the bundle
  // charset 'ascii' (esbuild's default) escapes every non-ASCII character, so
  // the C++ build can embed the bundle as plain raw string literals.
  charset: 'ascii',
  metafile: true,
  logLevel: 'warning',
});
const bytes = Object.values(result.metafile.outputs).reduce((n, o) => n + o.bytes, 0);
console.log(`viewer: ${outfile} ${(bytes / 1024).toFixed(0)} KiB`);
