// Prints the Khronos glTF validator's error and warning counts for each file given, as JSON lines.
// Usage: node tests/gltf_validate.mjs FILE...   (with NODE_PATH pointing at gltf-validator)
import { createRequire } from 'module';
import { readFileSync } from 'fs';
const require = createRequire(import.meta.url);
const validator = require('gltf-validator');
for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    externalResourceFunction: () => Promise.reject(new Error('external resources are not expected')),
  });
  const errors = report.issues.messages.filter((m) => m.severity === 0).map((m) => `${m.code}: ${m.message} (${m.pointer || ''})`);
  console.log(JSON.stringify({ file, errors: report.issues.numErrors, warnings: report.issues.numWarnings, first: errors.slice(0, 3) }));
}
