// Renders the start of the example lathe program with this extension's TextMate grammar, tokenized
// by vscode-textmate + vscode-oniguruma (what VS Code uses), coloured with VS Code's Dark+ colours
// per scope, as screenshot/render.html; screenshot.sh photographs it with headless Chromium.
'use strict';
const fs = require('fs');
const path = require('path');
const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const wasm = fs.readFileSync(require.resolve('vscode-oniguruma/release/onig.wasm')).buffer;
const onigLib = oniguruma.loadWASM(wasm).then(() => ({
  createOnigScanner: (p) => new oniguruma.OnigScanner(p),
  createOnigString: (s) => new oniguruma.OnigString(s),
}));
const registry = new vsctm.Registry({
  onigLib,
  loadGrammar: async () =>
    vsctm.parseRawGrammar(
      fs.readFileSync(path.join(__dirname, '../syntaxes/ncplc-plc.tmLanguage.json'), 'utf8'),
      'ncplc-plc.tmLanguage.json'
    ),
});
// Dark+ colours of the scopes the grammar produces (most specific prefix first).
const colours = [
  ['comment', '#6A9955'],
  ['keyword.control', '#C586C0'],
  ['keyword.operator.word', '#569CD6'],
  ['keyword.operator', '#D4D4D4'],
  ['keyword', '#569CD6'],
  ['storage', '#569CD6'],
  ['constant.numeric', '#B5CEA8'],
  ['constant.language', '#569CD6'],
  ['support.function', '#DCDCAA'],
  ['variable.other.signal.input', '#4EC9B0'],
  ['variable.other.signal.output', '#CE9178'],
  ['variable.other.signal.byte', '#D7BA7D'],
  ['variable.other.pulse', '#C586C0'],
  ['variable', '#9CDCFE'],
];
const colour = (scopes) => {
  for (const s of scopes.slice().reverse()) {
    const c = colours.find(([p]) => s.startsWith(p));
    if (c) return c[1];
  }
  return '#D4D4D4';
};
const esc = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
registry.loadGrammar('source.ncplc-plc').then((grammar) => {
  const src = fs.readFileSync(path.join(__dirname, '../../../plc-programs/lathe/MP0/PLCPRG'), 'utf8');
  const lines = src.split('\n').slice(26, 74);
  let state = vsctm.INITIAL;
  const html = lines.map((line) => {
    const r = grammar.tokenizeLine(line, state);
    state = r.ruleStack;
    return r.tokens
      .map((t) => `<span style="color:${colour(t.scopes)}">${esc(line.substring(t.startIndex, t.endIndex))}</span>`)
      .join('');
  });
  fs.writeFileSync(
    path.join(__dirname, 'render.html'),
    `<html><body style="margin:0;background:#1E1E1E"><pre style="font:14px/19px 'DejaVu Sans Mono',monospace;padding:12px;margin:0">${html.join('\n')}</pre></body></html>`
  );
});
