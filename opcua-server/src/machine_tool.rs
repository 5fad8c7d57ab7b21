//! The instance of the OPC UA for Machine Tools model (OPC 40501-1) for the running machine, under
//! `Objects/Machines` (OPC 40001-1): `MachineToolType` with `Identification`, `Monitoring`
//! (`MachineTool`, one `Channel<n>` per process, `Stacklight`; in a part run one `Spindle<n>` per
//! process and the channels' methods), `Production/ActiveProgram` (with the kernel's blocks
//! executed in a part run) and `Notification/Messages` (alarms and PLC messages as events). The types come from the vendored NodeSets
//! ([`crate::nodesets`]); the instance nodes are in the server's namespace, with the browse names
//! and type definitions the types declare. [`crate::values::Evaluator`] turns a frame into their
//! values.
//!
//! **Invariant:** each value node has exactly one [`Source`]; the evaluator sets a node only when
//! its value changed, stamped with the tick's time like the signals.

use hmi::Command;
use opcua::nodes::{
    EventNotifier, MethodBuilder, ObjectBuilder, ReferenceDirection, VariableBuilder,
};
use opcua::server::address_space::AddressSpace;
use opcua::types::{
    Argument, DataTypeId, LocalizedText, NodeId, ObjectId, QualifiedName, ReferenceTypeId,
    VariableTypeId, Variant,
};
use packets::Signal;

use crate::config::{Identification, Lamp};
use crate::derive::ProgramState;

/// The namespace indexes the instance uses.
#[derive(Debug, Clone, Copy)]
pub struct Ns {
    /// The server's own (instance nodes).
    pub own: u16,
    /// MachineTool.
    pub mt: u16,
    /// Machinery.
    pub machinery: u16,
    /// DI.
    pub di: u16,
    /// IA.
    pub ia: u16,
}

/// The interface-map signals of one process the channel shows.
#[derive(Debug, Clone, Copy, Default)]
pub struct ProcessRoles {
    /// The process (1..5).
    pub process: u8,
    /// CYCLE, HOLD, MODE, FOV, ROV (None: the map has none).
    pub cycle: Option<Signal>,
    /// See `cycle`.
    pub hold: Option<Signal>,
    /// See `cycle`.
    pub mode: Option<Signal>,
    /// See `cycle`.
    pub fov: Option<Signal>,
    /// See `cycle`.
    pub rov: Option<Signal>,
    /// The spindle override (SOV).
    pub sov: Option<Signal>,
    /// The programmed spindle speed (SCODE, the first byte of a binary dword).
    pub scode: Option<Signal>,
}

/// What the instance shows.
#[derive(Debug, Clone, Default)]
pub struct Inputs {
    /// The machine's name (the machine directory's).
    pub name: String,
    /// The nameplate (io.toml `[identification]`).
    pub identification: Identification,
    /// The processes, process 1 first.
    pub processes: Vec<ProcessRoles>,
    /// The stack light, top first.
    pub lamps: Vec<Lamp>,
    /// The partprogram of the run (`--program`), if any.
    pub program: Option<String>,
    /// A part run's kernel runs beside the scan: each channel gets `Start`, `Hold`, `Reset`, each
    /// process a `Spindle<n>`, the active program its blocks executed.
    pub commands: bool,
}

/// What [`add`] put into the address space that the server serves.
#[derive(Debug, Default)]
pub struct Added {
    /// The value nodes and their sources.
    pub values: Vec<(NodeId, Source)>,
    /// The methods: node, process, command.
    pub methods: Vec<(NodeId, u8, Command)>,
}

/// How a value node's value follows the image.
#[derive(Debug, Clone, Copy)]
pub enum Source {
    /// `ChannelState` from CYCLE and HOLD.
    ChannelState(Option<Signal>, Option<Signal>),
    /// `ChannelMode` from MODE.
    ChannelMode(Option<Signal>),
    /// `MachineOperationMode` from MODE.
    OperationMode(Option<Signal>),
    /// An override in % (Double) from its byte.
    Percent(Option<Signal>),
    /// A Boolean from a bit.
    Bit(Signal),
    /// The active program's `CurrentState` (LocalizedText) from CYCLE and HOLD.
    ProgramState(Option<Signal>, Option<Signal>),
    /// The `Id` of the program's `CurrentState`.
    ProgramStateId(Option<Signal>, Option<Signal>),
    /// The kernel's blocks executed of a process (UInt64; index = process − 1).
    Blocks(usize),
    /// The kernel's actual spindle speed of a process (Double, rev/min).
    SpindleRpm(usize),
    /// Whether that spindle turns (Boolean).
    Rotating(usize),
    /// A binary little-endian dword from its first byte (Double).
    Dword(Option<Signal>),
}

/// The id of the MachineTool object.
pub const ROOT: &str = "MachineTool";
/// The id of the `Messages` object (the alarms' event notifier).
pub const MESSAGES: &str = "MachineTool/Notification/Messages";

struct Build<'a> {
    space: &'a mut AddressSpace,
    ns: Ns,
    values: Vec<(NodeId, Source)>,
    methods: Vec<(NodeId, u8, Command)>,
}

impl Build<'_> {
    fn id(&self, path: &str) -> NodeId {
        NodeId::new(self.ns.own, path)
    }

    /// An object `path` (browse name `bn`) of type `ty`, a component of `parent`.
    fn object(&mut self, path: &str, bn: QualifiedName, ty: NodeId, parent: &str) -> NodeId {
        let id = self.id(path);
        let display = bn.name.to_string();
        ObjectBuilder::new(&id, bn, display.as_str())
            .has_type_definition(ty)
            .component_of(self.id(parent))
            .insert(self.space);
        id
    }

    /// A variable `path` with a fixed or changing value; `property` makes it a property.
    #[allow(clippy::too_many_arguments)]
    fn variable(
        &mut self,
        path: &str,
        bn: QualifiedName,
        data_type: NodeId,
        value: Variant,
        parent: &str,
        property: bool,
        source: Option<Source>,
    ) {
        let id = self.id(path);
        let display = bn.name.to_string();
        let b = VariableBuilder::new(&id, bn, display.as_str())
            .data_type(data_type)
            .value_rank(-1)
            .value(value);
        let b = if property {
            b.property_of(self.id(parent))
                .has_type_definition(VariableTypeId::PropertyType)
        } else {
            b.component_of(self.id(parent))
                .has_type_definition(VariableTypeId::BaseDataVariableType)
        };
        b.insert(self.space);
        if let Some(s) = source {
            self.values.push((id, s));
        }
    }
}

/// Adds the instance to `space`; the value nodes with their sources, and the methods.
pub fn add(space: &mut AddressSpace, ns: Ns, inputs: &Inputs) -> Added {
    let mut b = Build {
        space,
        ns,
        values: Vec::new(),
        methods: Vec::new(),
    };
    let (mt, di, machinery, ia) = (ns.mt, ns.di, ns.machinery, ns.ia);
    let root = b.id(ROOT);
    ObjectBuilder::new(
        &root,
        QualifiedName::new(ns.own, inputs.name.as_str()),
        inputs.name.as_str(),
    )
    .description("The machine tool (OPC 40501-1 MachineToolType)")
    .has_type_definition(NodeId::new(mt, 13u32))
    .organized_by(NodeId::new(machinery, 1001u32))
    .organized_by(NodeId::from(ObjectId::ObjectsFolder))
    .insert(b.space);
    identification(&mut b, &inputs.identification, &inputs.name);
    b.object(
        "MachineTool/Monitoring",
        QualifiedName::new(mt, "Monitoring"),
        NodeId::new(mt, 14u32),
        ROOT,
    );
    let p1 = inputs.processes.first().copied().unwrap_or_default();
    b.object(
        "MachineTool/Monitoring/MachineTool",
        QualifiedName::new(mt, "MachineTool"),
        NodeId::new(mt, 26u32),
        "MachineTool/Monitoring",
    );
    b.variable(
        "MachineTool/Monitoring/MachineTool/Name",
        QualifiedName::new(mt, "Name"),
        DataTypeId::String.into(),
        Variant::from(inputs.name.as_str()),
        "MachineTool/Monitoring/MachineTool",
        true,
        None,
    );
    b.variable(
        "MachineTool/Monitoring/MachineTool/OperationMode",
        QualifiedName::new(mt, "OperationMode"),
        NodeId::new(mt, 65u32),
        Variant::Int32(5),
        "MachineTool/Monitoring/MachineTool",
        false,
        Some(Source::OperationMode(p1.mode)),
    );
    b.variable(
        "MachineTool/Monitoring/MachineTool/FeedOverride",
        QualifiedName::new(mt, "FeedOverride"),
        DataTypeId::Double.into(),
        Variant::Double(0.0),
        "MachineTool/Monitoring/MachineTool",
        false,
        Some(Source::Percent(p1.fov)),
    );
    for p in &inputs.processes {
        channel(&mut b, p);
        if inputs.commands {
            commands(&mut b, p.process);
            spindle(&mut b, p);
        }
    }
    stacklight(&mut b, &inputs.lamps, ia);
    production(&mut b, inputs.program.as_deref(), p1, inputs.commands);
    b.object(
        "MachineTool/Notification",
        QualifiedName::new(mt, "Notification"),
        NodeId::new(mt, 7u32),
        ROOT,
    );
    let messages = b.id(MESSAGES);
    ObjectBuilder::new(&messages, QualifiedName::new(mt, "Messages"), "Messages")
        .description("The kernel's and the I/O's alarms and the PLC's messages as events (raised and cleared)")
        .has_type_definition(NodeId::new(mt, 38u32))
        .event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS)
        .component_of(b.id("MachineTool/Notification"))
        .insert(b.space);
    let _ = di;
    Added {
        values: b.values,
        methods: b.methods,
    }
}

/// The operator's methods of channel `process`: `Start` (CYCLE START), `Hold` (FEED HOLD) and
/// `Reset`, without inputs; the output is the tick the kernel took the command at.
fn commands(b: &mut Build<'_>, process: u8) {
    let own = b.ns.own;
    let channel = format!("MachineTool/Monitoring/Channel{process}");
    for (name, command, what) in [
        ("Start", Command::Start, "CYCLE START"),
        ("Hold", Command::Hold, "FEED HOLD"),
        ("Reset", Command::Reset, "RESET"),
    ] {
        let path = format!("{channel}/{name}");
        let id = b.id(&path);
        let out = b.id(&format!("{path}/OutputArguments"));
        let tick = Argument {
            name: "Tick".into(),
            data_type: DataTypeId::UInt64.into(),
            value_rank: -1,
            array_dimensions: None,
            description: LocalizedText::new("", "the tick the kernel took the command at"),
        };
        MethodBuilder::new(&id, QualifiedName::new(own, name), name)
            .description(format!("{what} of process {process} (operator role)"))
            .component_of(b.id(&channel))
            .executable(true)
            .user_executable(true)
            .output_args(b.space, &out, &[tick])
            .insert(b.space);
        b.methods.push((id, process, command));
    }
}

fn identification(b: &mut Build<'_>, id: &Identification, name: &str) {
    let (mt, di, machinery) = (b.ns.mt, b.ns.di, b.ns.machinery);
    let path = "MachineTool/Identification";
    ObjectBuilder::new(
        &b.id(path),
        QualifiedName::new(di, "Identification"),
        "Identification",
    )
    .has_type_definition(NodeId::new(mt, 11u32))
    .reference(
        b.id(ROOT),
        ReferenceTypeId::HasAddIn,
        ReferenceDirection::Inverse,
    )
    .insert(b.space);
    let text = |s: &str| Variant::from(LocalizedText::new("", s));
    let model = if id.model.is_empty() { name } else { &id.model };
    for (bn, ns, ty, v) in [
        (
            "Manufacturer",
            di,
            DataTypeId::LocalizedText,
            text(&id.manufacturer),
        ),
        ("Model", di, DataTypeId::LocalizedText, text(model)),
        (
            "SerialNumber",
            di,
            DataTypeId::String,
            Variant::from(id.serial.as_str()),
        ),
        (
            "ProductInstanceUri",
            di,
            DataTypeId::String,
            Variant::from(format!("urn:ncplc:{}:{}", id.manufacturer, id.serial).as_str()),
        ),
        (
            "SoftwareRevision",
            di,
            DataTypeId::String,
            Variant::from(concat!("ncplc ", env!("CARGO_PKG_VERSION"))),
        ),
    ] {
        b.variable(
            &format!("{path}/{bn}"),
            QualifiedName::new(ns, bn),
            ty.into(),
            v,
            path,
            true,
            None,
        );
    }
    if let Some(year) = id.year {
        b.variable(
            &format!("{path}/YearOfConstruction"),
            QualifiedName::new(machinery, "YearOfConstruction"),
            DataTypeId::UInt16.into(),
            Variant::UInt16(year),
            path,
            true,
            None,
        );
    }
}

fn channel(b: &mut Build<'_>, p: &ProcessRoles) {
    let mt = b.ns.mt;
    let path = format!("MachineTool/Monitoring/Channel{}", p.process);
    let bn = format!("Channel{}", p.process);
    b.object(
        &path,
        QualifiedName::new(mt, bn.as_str()),
        NodeId::new(mt, 16u32),
        "MachineTool/Monitoring",
    );
    b.variable(
        &format!("{path}/Name"),
        QualifiedName::new(mt, "Name"),
        DataTypeId::String.into(),
        Variant::from(format!("process {}", p.process).as_str()),
        &path,
        true,
        None,
    );
    let values = [
        (
            "ChannelState",
            NodeId::new(mt, 64u32),
            Variant::Int32(2),
            Source::ChannelState(p.cycle, p.hold),
        ),
        (
            "ChannelMode",
            NodeId::new(mt, 67u32),
            Variant::Int32(7),
            Source::ChannelMode(p.mode),
        ),
        (
            "FeedOverride",
            DataTypeId::Double.into(),
            Variant::Double(0.0),
            Source::Percent(p.fov),
        ),
        (
            "RapidOverride",
            DataTypeId::Double.into(),
            Variant::Double(0.0),
            Source::Percent(p.rov),
        ),
    ];
    for (name, ty, v, s) in values {
        b.variable(
            &format!("{path}/{name}"),
            QualifiedName::new(mt, name),
            ty,
            v,
            &path,
            false,
            Some(s),
        );
    }
}

fn stacklight(b: &mut Build<'_>, lamps: &[Lamp], ia: u16) {
    if lamps.is_empty() {
        return;
    }
    let mt = b.ns.mt;
    let path = "MachineTool/Monitoring/Stacklight";
    b.object(
        path,
        QualifiedName::new(mt, "Stacklight"),
        NodeId::new(ia, 1002u32),
        "MachineTool/Monitoring",
    );
    b.variable(
        &format!("{path}/StacklightMode"),
        QualifiedName::new(ia, "StacklightMode"),
        NodeId::new(ia, 3002u32),
        Variant::Int32(0),
        path,
        true,
        None,
    );
    for (i, lamp) in lamps.iter().enumerate() {
        let lp = format!("{path}/Lamp{i}");
        let id = b.id(&lp);
        let bn = format!("Lamp{i}");
        ObjectBuilder::new(&id, QualifiedName::new(b.ns.own, bn.as_str()), bn.as_str())
            .description(format!("lit by {}", lamp.signal))
            .has_type_definition(NodeId::new(ia, 1006u32))
            .reference(
                b.id(path),
                ReferenceTypeId::HasOrderedComponent,
                ReferenceDirection::Inverse,
            )
            .insert(b.space);
        let n = u32::try_from(i).unwrap_or(u32::MAX);
        b.variable(
            &format!("{lp}/NumberInList"),
            QualifiedName::new(0, "NumberInList"),
            DataTypeId::UInt32.into(),
            Variant::UInt32(n),
            &lp,
            true,
            None,
        );
        b.variable(
            &format!("{lp}/SignalColor"),
            QualifiedName::new(ia, "SignalColor"),
            NodeId::new(ia, 3004u32),
            Variant::Int32(lamp.color),
            &lp,
            false,
            None,
        );
        b.variable(
            &format!("{lp}/SignalOn"),
            QualifiedName::new(ia, "SignalOn"),
            DataTypeId::Boolean.into(),
            Variant::Boolean(false),
            &lp,
            true,
            Some(Source::Bit(lamp.signal)),
        );
    }
}

/// `Monitoring/Spindle<n>` (`SpindleMonitoringType`): the override from SOV, `IsRotating` and
/// (ours) `ActualSpeed` in rev/min from the kernel, `CommandedSpeed` from SCODE.
fn spindle(b: &mut Build<'_>, p: &ProcessRoles) {
    let (mt, own) = (b.ns.mt, b.ns.own);
    let path = format!("MachineTool/Monitoring/Spindle{}", p.process);
    let bn = format!("Spindle{}", p.process);
    b.object(
        &path,
        QualifiedName::new(mt, bn.as_str()),
        NodeId::new(mt, 22u32),
        "MachineTool/Monitoring",
    );
    let at = usize::from(p.process).saturating_sub(1);
    b.variable(
        &format!("{path}/Name"),
        QualifiedName::new(mt, "Name"),
        DataTypeId::String.into(),
        Variant::from(format!("spindle of process {}", p.process).as_str()),
        &path,
        true,
        None,
    );
    for (name, ns, ty, v, s) in [
        (
            "Override",
            mt,
            DataTypeId::Double,
            Variant::Double(0.0),
            Source::Percent(p.sov),
        ),
        (
            "IsRotating",
            mt,
            DataTypeId::Boolean,
            Variant::Boolean(false),
            Source::Rotating(at),
        ),
        (
            "ActualSpeed",
            own,
            DataTypeId::Double,
            Variant::Double(0.0),
            Source::SpindleRpm(at),
        ),
        (
            "CommandedSpeed",
            own,
            DataTypeId::Double,
            Variant::Double(0.0),
            Source::Dword(p.scode),
        ),
    ] {
        b.variable(
            &format!("{path}/{name}"),
            QualifiedName::new(ns, name),
            ty.into(),
            v,
            &path,
            false,
            Some(s),
        );
    }
}

fn production(b: &mut Build<'_>, program: Option<&str>, p1: ProcessRoles, kernel: bool) {
    let mt = b.ns.mt;
    b.object(
        "MachineTool/Production",
        QualifiedName::new(mt, "Production"),
        NodeId::new(mt, 21u32),
        ROOT,
    );
    let path = "MachineTool/Production/ActiveProgram";
    b.object(
        path,
        QualifiedName::new(mt, "ActiveProgram"),
        NodeId::new(mt, 32u32),
        "MachineTool/Production",
    );
    b.variable(
        &format!("{path}/Name"),
        QualifiedName::new(mt, "Name"),
        DataTypeId::String.into(),
        Variant::from(program.unwrap_or("")),
        path,
        true,
        None,
    );
    b.variable(
        &format!("{path}/NumberInList"),
        QualifiedName::new(0, "NumberInList"),
        DataTypeId::UInt16.into(),
        Variant::UInt16(0),
        path,
        true,
        None,
    );
    if kernel {
        b.variable(
            &format!("{path}/BlocksExecuted"),
            QualifiedName::new(b.ns.own, "BlocksExecuted"),
            DataTypeId::UInt64.into(),
            Variant::UInt64(0),
            path,
            false,
            Some(Source::Blocks(usize::from(p1.process).saturating_sub(1))),
        );
    }
    let state = format!("{path}/State");
    b.object(
        &state,
        QualifiedName::new(mt, "State"),
        NodeId::new(mt, 24u32),
        path,
    );
    let cs = format!("{state}/CurrentState");
    let id = b.id(&cs);
    VariableBuilder::new(&id, QualifiedName::new(0, "CurrentState"), "CurrentState")
        .data_type(DataTypeId::LocalizedText)
        .value_rank(-1)
        .value(LocalizedText::new("", "Initializing"))
        .component_of(b.id(&state))
        .has_type_definition(VariableTypeId::FiniteStateVariableType)
        .insert(b.space);
    b.values.push((id, Source::ProgramState(p1.cycle, p1.hold)));
    b.variable(
        &format!("{cs}/Id"),
        QualifiedName::new(0, "Id"),
        DataTypeId::NodeId.into(),
        Variant::from(NodeId::new(mt, ProgramState::Initializing.type_node())),
        &cs,
        true,
        Some(Source::ProgramStateId(p1.cycle, p1.hold)),
    );
}
