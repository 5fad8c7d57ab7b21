#!/usr/bin/env bash
# Builds editors/vscode/ncplc-plc.vsix with the npm toolchain: installs the locked dependencies
# (vscode-languageclient, @vscode/vsce) and runs `vsce package`, which also validates the
# manifest (package.json) and the files it names (the grammar, the language configuration).
set -euo pipefail
cd "$(dirname "$0")"
# The grammar and the language configuration must at least be valid JSON.
node -e 'for (const f of ["syntaxes/ncplc-plc.tmLanguage.json", "language-configuration.json", "package.json"]) JSON.parse(require("fs").readFileSync(f, "utf8"))'
# Every grammar pattern must compile as a JavaScript regular expression (Oniguruma's (?i) aside).
node -e '
const g = JSON.parse(require("fs").readFileSync("syntaxes/ncplc-plc.tmLanguage.json", "utf8"));
const walk = (o) => { if (o && typeof o === "object") { for (const [k, v] of Object.entries(o)) {
  if (k === "match") new RegExp(v.replace(/^\(\?i\)/, ""), "i"); else walk(v); } } };
walk(g.repository);'
npm ci --no-audit --no-fund --loglevel=error
npx vsce package --allow-missing-repository --no-rewrite-relative-links --out ncplc-plc.vsix
ls -l ncplc-plc.vsix
