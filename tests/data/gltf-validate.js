// Validates a glTF file with the Khronos validator; prints the report's issue counts as JSON.
const validator = require('gltf-validator');
const fs = require('fs');
const path = process.argv[2];
validator.validateBytes(new Uint8Array(fs.readFileSync(path)), { maxIssues: 50 })
  .then((r) => { console.log(JSON.stringify({ errors: r.issues.numErrors, warnings: r.issues.numWarnings, messages: r.issues.messages.slice(0, 10) })); })
  .catch((e) => { console.error(String(e)); process.exit(2); });
