// Validates a .glb with the Khronos glTF-Validator (npm gltf-validator), as the
// C++ test tests/recording/gltf_validator_test.cpp does:
//   node viewer/test/validate-gltf.mjs FILE.glb
// Prints one JSON line with the issue counts and messages; exit 0 when the
// validator reports no errors and no warnings, 1 otherwise.
import { readFileSync } from 'node:fs';
import validator from 'gltf-validator';

const file = process.argv[2];
if (!file) {
  console.error('usage: validate-gltf.mjs FILE.glb');
  process.exit(2);
}
try {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    maxIssues: 50,
    // Resolving external resources is not needed: a .glb carries everything.
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri} requested`)),
  });
  const issues = report.issues;
  const summary = {
    file,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    animations: report.info?.animationCount,
    messages: issues.messages.map((m) => `${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`),
  };
  console.log(JSON.stringify(summary));
  process.exit(issues.numErrors === 0 && issues.numWarnings === 0 ? 0 : 1);
} catch (e) {
  console.log(JSON.stringify({ file, failure: String(e?.message ?? e) }));
  process.exit(1);
}
