//! The PLC language server (`ncplc lsp`) and formatter (`ncplc fmt`): diagnostics as you type
//! with the codes, messages and hints of `ncplc build`, hover, go to definition, references,
//! completion, rename, formatting, document and workspace symbols, semantic tokens and a running
//! controller's power flow as inlay hints, over stdio with lsp-server (docs/editor.md).
//!
//! Layers: [`text`] (positions and edits) → [`analysis`] (one document: its diagnostics through
//! `compiler::diagnose_incremental` and its [`index`]) → the features ([`hover`], [`navigate`],
//! [`complete`], [`tokens`], [`format`], [`flow`]) → [`server`] (the protocol loop, debouncing). Nothing
//! here depends on the runtime; the `ncplc` binary only calls [`serve_stdio`] and, for `ncplc fmt`,
//! [`format::format`].

pub mod analysis;
pub mod complete;
pub mod flow;
pub mod format;
pub mod hover;
pub mod index;
pub mod keywords;
pub mod machine;
pub mod navigate;
pub mod server;
pub mod text;
pub mod tokens;
pub mod uri;

pub use server::{ServerError, serve, serve_stdio};
