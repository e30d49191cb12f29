// Validates a .glb with the Khronos glTF validator; prints the report's counts and
// first messages as JSON; exits 1 on any error or warning.
const fs = require('fs');
const validator = require('gltf-validator');

const path = process.argv[2];
const data = new Uint8Array(fs.readFileSync(path));
validator.validateBytes(data).then((report) => {
  const issues = report.issues;
  console.log(JSON.stringify({
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    messages: issues.messages.slice(0, 10),
  }));
  process.exit(issues.numErrors + issues.numWarnings > 0 ? 1 : 0);
}).catch((e) => {
  console.error(String(e));
  process.exit(2);
});
