// Validates one .glb or .gltf with the Khronos glTF validator and prints the
// report's issue counts and messages.
//
//   node validate.mjs FILE
//
// Exit codes: 0 no errors (warnings, infos and hints are printed but allowed),
// 1 the validator found errors (or could not run), 2 usage error.
// Install the validator first: npm ci --prefix tests/runtime/io/gltf_validator
import fs from 'node:fs/promises';
import path from 'node:path';
import validator from 'gltf-validator';

const SEVERITY = ['error', 'warning', 'info', 'hint'];

async function main(argv) {
  if (argv.length !== 1 || argv[0].startsWith('-')) {
    console.error('usage: node validate.mjs FILE.glb|FILE.gltf');
    return 2;
  }
  const file = path.resolve(argv[0]);
  let bytes;
  try {
    bytes = new Uint8Array(await fs.readFile(file));
  } catch (error) {
    console.error(`${file}: cannot read: ${error.message}`);
    return 2;
  }
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,  // report every issue, not the first 100
    // Resources outside a data URI are read from beside the file.
    externalResourceFunction: (uri) =>
      fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))
        .then((data) => new Uint8Array(data)),
  });
  const issues = report.issues;
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
              `${issues.numInfos} infos, ${issues.numHints} hints` +
              (issues.truncated ? ' (truncated)' : ''));
  for (const message of issues.messages) {
    const where = message.pointer ?? (message.offset !== undefined ? `@${message.offset}` : '');
    console.log(`  ${SEVERITY[message.severity] ?? message.severity} ${message.code}: ` +
                `${message.message}${where ? ` (${where})` : ''}`);
  }
  return issues.numErrors > 0 ? 1 : 0;
}

main(process.argv.slice(2)).then(
  (code) => process.exit(code),
  (error) => {
    console.error(`validator failed: ${error?.stack ?? error}`);
    process.exit(1);
  });
