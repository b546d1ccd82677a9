// Validates glTF / GLB files with the Khronos glTF validator.
// Usage: node validate.mjs FILE...   Prints one JSON summary per file; exit 1 if any
// file has errors (warnings and infos are reported, not fatal).
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import validator from 'gltf-validator';

let failed = false;
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 50,
    externalResourceFunction: (uri) =>
      readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  const { numErrors, numWarnings, numInfos, messages } = report.issues;
  console.log(JSON.stringify({ file, numErrors, numWarnings, numInfos,
                               messages: messages.filter((m) => m.severity <= 1).slice(0, 20) }));
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
