//! The OPC UA for Machine Tools model (OPC 40501-1) and what it is built on, as the OPC Foundation
//! publishes it: the NodeSet2 files of DI, IA, Machinery, ISA95-JOBCONTROL, Machinery/Jobs and
//! MachineTool, vendored in `opcua-server/nodesets/` with their OPC Foundation MIT licence headers
//! (UA-Nodeset a2d4ae8, MachineTool 1.02.0 of 2024-11-01) and compiled into the binary. They are
//! loaded at start with async-opcua's `xml` feature into a node manager of their own.
//!
//! **Invariant:** the files are imported in dependency order; each names the namespaces it needs
//! in its own `NamespaceUris`, so no file needs extra dependent namespaces.

use opcua::nodes::{NodeSet2Import, NodeSetImport};

/// The MachineTool namespace.
pub const MACHINE_TOOL: &str = "http://opcfoundation.org/UA/MachineTool/";
/// The Machinery namespace.
pub const MACHINERY: &str = "http://opcfoundation.org/UA/Machinery/";
/// The DI namespace.
pub const DI: &str = "http://opcfoundation.org/UA/DI/";
/// The IA namespace.
pub const IA: &str = "http://opcfoundation.org/UA/IA/";

/// The files, in import order.
const FILES: [(&str, &str); 6] = [
    ("DI", include_str!("../nodesets/Opc.Ua.Di.NodeSet2.xml")),
    ("IA", include_str!("../nodesets/Opc.Ua.IA.NodeSet2.xml")),
    (
        "Machinery",
        include_str!("../nodesets/Opc.Ua.Machinery.NodeSet2.xml"),
    ),
    (
        "ISA95-JOBCONTROL",
        include_str!("../nodesets/opc.ua.isa95-jobcontrol.nodeset2.xml"),
    ),
    (
        "Machinery/Jobs",
        include_str!("../nodesets/Opc.Ua.Machinery.Jobs.Nodeset2.xml"),
    ),
    (
        "MachineTool",
        include_str!("../nodesets/Opc.Ua.MachineTool.NodeSet2.xml"),
    ),
];

/// The importers of the six NodeSets, or which file failed to parse.
pub fn imports() -> Result<Vec<Box<dyn NodeSetImport>>, String> {
    FILES
        .iter()
        .map(|(name, xml)| {
            NodeSet2Import::new_str("en", xml, Vec::new())
                .map(|i| Box::new(i) as Box<dyn NodeSetImport>)
                .map_err(|e| format!("the {name} NodeSet: {e}"))
        })
        .collect()
}
