// The ncplc PLC language client: starts `ncplc lsp` (setting `ncplc.path`) over stdio for the
// documents of language `ncplc-plc` (PLCPRG files and *.plc). Plain JavaScript: no build step.
'use strict';

const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration('ncplc');
  const command = config.get('path', 'ncplc');
  const run = { command, args: ['lsp'], transport: TransportKind.stdio };
  client = new LanguageClient(
    'ncplc',
    'ncplc PLC language server',
    { run, debug: run },
    {
      documentSelector: [{ language: 'ncplc-plc' }],
      initializationOptions: {
        debounceMs: config.get('debounceMs', 150),
        ...(config.get('hmi', '') ? { hmi: config.get('hmi', '') } : {}),
      },
    }
  );
  context.subscriptions.push({ dispose: () => client && client.stop() });
  return client.start().catch((e) => {
    vscode.window.showErrorMessage(
      `ncplc: cannot start \`${command} lsp\` (${e.message}); set "ncplc.path" to the ncplc binary`
    );
  });
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
