// Validates glTF files with the Khronos glTF validator: prints each file's
// counts and its issues; exits 1 when any file has an error or a warning.
//   node tools/web/validate_gltf.mjs FILE.glb [FILE.gltf ...]
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import validator from 'gltf-validator';

let failed = false;
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    externalResourceFunction: (uri) =>
      readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then(
        (data) => new Uint8Array(data)),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
              `${i.numHints} hints`);
  for (const m of i.messages) {
    const severity = ['error', 'warning', 'info', 'hint'][m.severity];
    console.log(`  ${severity} ${m.code} at ${m.pointer ?? ''}: ${m.message}`);
  }
  if (i.numErrors > 0 || i.numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);
