#!/usr/bin/env node
// Validates glTF / GLB files with the Khronos glTF-Validator (npm package `gltf-validator`)
// and prints one summary line per file, then each issue.
//
// Usage: node scripts/validate_gltf.mjs FILE.glb [FILE.glb ...]
// Exit: 0 no errors (warnings allowed), 1 a file has errors, 2 bad usage or unreadable file,
//       3 the validator is not installed.
// The validator is looked up in $GLTF_VALIDATOR_MODULE, then .ci/node (where .ci/run installs
// it: npm install --prefix .ci/node --no-save gltf-validator@2.0.0-dev.3.10), then the usual
// node module paths.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const require = createRequire(import.meta.url);
const candidates = [
  process.env.GLTF_VALIDATOR_MODULE,
  join(here, '..', '.ci', 'node', 'node_modules', 'gltf-validator'),
  'gltf-validator',
].filter(Boolean);

let validator = null;
for (const c of candidates) {
  try {
    validator = require(c);
    break;
  } catch {
    // try the next place
  }
}
if (validator === null) {
  console.error(
    'gltf-validator is not installed: npm install --prefix .ci/node --no-save gltf-validator@2.0.0-dev.3.10',
  );
  process.exit(3);
}

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node scripts/validate_gltf.mjs FILE.glb [FILE.glb ...]');
  process.exit(2);
}

const severities = ['error', 'warning', 'info', 'hint'];
let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(readFileSync(file));
  } catch (e) {
    console.error(`${file}: cannot read (${e.message})`);
    process.exit(2);
  }
  let report;
  try {
    report = await validator.validateBytes(bytes, { uri: file, maxIssues: 200 });
  } catch (e) {
    console.log(`${file}: 1 errors (not glTF: ${e})`);
    failed = true;
    continue;
  }
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(
    `${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints (gltf-validator ${report.validatorVersion})`,
  );
  for (const m of messages) {
    console.log(`  ${severities[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
