// Bundles the live sandbox (src/sandbox.js + three.js + apps/web/fulcrum_api.js)
// into one classic script, so the page works from file:// (docs/browser.md).
// Usage: node build-sandbox.mjs OUTFILE   (scripts/build-wasm.sh runs it)
import { build } from 'esbuild';

const outfile = process.argv[2] ?? '../build-wasm/sandbox.js';
await build({
  entryPoints: ['src/sandbox.js'],
  bundle: true,
  minify: true,
  format: 'iife',
  target: ['es2020'],
  outfile,
  legalComments: 'eof',   // keep three.js's MIT licence notice in the bundle
  logLevel: 'warning',
});
console.log(`sandbox: ${outfile}`);
