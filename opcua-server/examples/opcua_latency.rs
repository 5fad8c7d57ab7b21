//! A fast, independent OPC UA client for the latency bench (`opcua-server/bench/scan_cost.py
//! --client rust`): async-opcua's own client (not our server code) connects to a running `ncplc
//! run … --opcua`, subscribes to `Signals/Tick` and 99 bytes of packet K (the Python client's
//! items) at a publishing and sampling interval of one tick, keeps the client's usual Publish
//! requests outstanding (async-opcua sends at least two per subscription), and after `SECONDS`
//! prints one line of JSON: the notifications and, in ms, the percentiles of
//! - `lat`: receive time − the value's server timestamp (the wall-clock time of the scan's copy of
//!   that tick, same host and clock): what the client sees;
//! - `srv`: the notification message's publish time − the server timestamp: the server's part up
//!   to the publish cycle that took the value (publisher poll, sampling, publishing timer, and a
//!   wait for a Publish request when none was queued);
//! - `wire`: receive time − publish time: encoding, the socket and the client's decoding.
//!
//! The first notification of each item is its current value (stamped when it last changed, maybe
//! seconds ago) and is not counted. Usage: `opcua_latency URL SECONDS [INTERVAL_MS]`.

use std::collections::HashSet;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use opcua::types::{
    AttributeId, DataChangeNotification, DataValue, DateTime, MessageSecurityMode,
    MonitoredItemCreateRequest, NodeId, NotificationMessage, ReadValueId, TimestampsToReturn,
    UserTokenPolicy, VariableId, Variant,
};
use opcua_client::{
    ClientBuilder, IdentityToken, MonitoredItemMap, OnSubscriptionNotificationCore, Session,
};

/// The latencies gathered, in µs.
#[derive(Default)]
struct Samples {
    /// Items whose first (current-value) notification has been seen.
    seen: HashSet<u32>,
    lat: Vec<i64>,
    srv: Vec<i64>,
    wire: Vec<i64>,
}

/// µs since the Unix epoch of an OPC UA time.
fn unix_us(t: &DateTime) -> i64 {
    t.as_chrono().timestamp_micros()
}

/// The subscription's callback: takes the receive time once per message.
struct Recorder(Arc<Mutex<Samples>>);

impl OnSubscriptionNotificationCore for Recorder {
    fn on_subscription_notification(
        &mut self,
        notification: NotificationMessage,
        _items: MonitoredItemMap<'_>,
    ) {
        let now = unix_us(&DateTime::now());
        let published = unix_us(&notification.publish_time);
        let Ok(mut s) = self.0.lock() else {
            return;
        };
        for obj in notification.notification_data.into_iter().flatten() {
            let Some(change) = obj.inner_as::<DataChangeNotification>() else {
                continue;
            };
            for item in change.monitored_items.iter().flatten() {
                if s.seen.insert(item.client_handle) {
                    continue;
                }
                if let Some(ts) = &item.value.server_timestamp {
                    let ts = unix_us(ts);
                    s.lat.push(now - ts);
                    s.srv.push(published - ts);
                    s.wire.push(now - published);
                }
            }
        }
    }
}

/// `"name":{"p50":…,"p99":…,"max":…}` in ms (index n/2 and ⌊0.99 n⌋ of the sorted samples, as
/// the bench script computes the Python client's).
fn percentiles(name: &str, v: &mut [i64]) -> String {
    v.sort_unstable();
    let at = |i: usize| {
        v.get(i.min(v.len().saturating_sub(1)))
            .map_or(0.0, |&x| x as f64 / 1e3)
    };
    let p99 = v.len() * 99 / 100;
    format!(
        "\"{name}\":{{\"p50\":{:.2},\"p99\":{:.2},\"max\":{:.2}}}",
        at(v.len() / 2),
        at(p99),
        at(v.len().saturating_sub(1))
    )
}

/// The namespace index of `urn:ncplc`.
async fn own_namespace(session: &Session) -> Result<u16, String> {
    let read = ReadValueId {
        node_id: VariableId::Server_NamespaceArray.into(),
        attribute_id: AttributeId::Value as u32,
        ..Default::default()
    };
    let values: Vec<DataValue> = session
        .read(&[read], TimestampsToReturn::Neither, 0.0)
        .await
        .map_err(|e| format!("read NamespaceArray: {e}"))?;
    let Some(Variant::Array(array)) = values.into_iter().next().and_then(|v| v.value) else {
        return Err("NamespaceArray is not an array".into());
    };
    array
        .values
        .iter()
        .position(|v| matches!(v, Variant::String(s) if s.as_ref() == "urn:ncplc"))
        .and_then(|i| u16::try_from(i).ok())
        .ok_or_else(|| "the server has no namespace urn:ncplc".into())
}

/// Connects, subscribes, waits `seconds` and returns the JSON line.
async fn run(url: &str, seconds: f64, interval_ms: u64) -> Result<String, String> {
    let pki = std::env::temp_dir().join(format!("ncplc-latency-pki-{}", std::process::id()));
    let mut client = ClientBuilder::new()
        .application_name("ncplc latency client")
        .application_uri("urn:ncplc:latency")
        .pki_dir(&pki)
        .create_sample_keypair(false)
        .trust_server_certs(true)
        .session_retry_limit(0)
        .client()
        .map_err(|e| e.join("; "))?;
    let endpoint: opcua::types::EndpointDescription = (
        url,
        "None",
        MessageSecurityMode::None,
        UserTokenPolicy::anonymous(),
    )
        .into();
    let (session, event_loop) = client
        .connect_to_matching_endpoint(endpoint, IdentityToken::Anonymous)
        .await
        .map_err(|e| format!("connect {url}: {e}"))?;
    let events = event_loop.spawn();
    session.wait_for_connection().await;
    let ns = own_namespace(&session).await?;
    let mut ids = vec![NodeId::new(ns, "Signals/Tick")];
    'outer: for conn in 0..25 {
        for b in 0..4 {
            if ids.len() == 100 {
                break 'outer;
            }
            ids.push(NodeId::new(ns, format!("Signals/K/{conn}/W{conn}K{b}")));
        }
    }
    let samples = Arc::new(Mutex::new(Samples::default()));
    let interval = Duration::from_millis(interval_ms);
    let sub = session
        .create_subscription(
            interval,
            3000,
            100,
            0,
            0,
            true,
            Recorder(Arc::clone(&samples)),
        )
        .await
        .map_err(|e| format!("create subscription: {e}"))?;
    let items: Vec<MonitoredItemCreateRequest> = ids
        .into_iter()
        .map(|id| {
            let mut r: MonitoredItemCreateRequest = id.into();
            r.requested_parameters.sampling_interval = interval_ms as f64;
            r.requested_parameters.queue_size = 100;
            r
        })
        .collect();
    let created = session
        .create_monitored_items(sub, TimestampsToReturn::Both, items)
        .await
        .map_err(|e| format!("create monitored items: {e}"))?;
    let bad = created
        .iter()
        .filter(|c| !c.result.status_code.is_good())
        .count();
    if bad > 0 {
        return Err(format!("{bad} monitored items were refused"));
    }
    tokio::time::sleep(Duration::from_secs_f64(seconds)).await;
    let _ = session.disconnect().await;
    events.abort();
    let _ = std::fs::remove_dir_all(&pki);
    let mut s = samples.lock().map_err(|e| e.to_string())?;
    let notes = s.lat.len();
    let (lat, srv, wire) = (
        percentiles("lat", &mut s.lat),
        percentiles("srv", &mut s.srv),
        percentiles("wire", &mut s.wire),
    );
    Ok(format!(
        "{{\"items\":{},\"notes\":{notes},{lat},{srv},{wire}}}",
        created.len()
    ))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(url), Some(seconds)) = (args.get(1), args.get(2).and_then(|s| s.parse::<f64>().ok()))
    else {
        eprintln!("usage: opcua_latency URL SECONDS [INTERVAL_MS]");
        std::process::exit(2);
    };
    let interval_ms = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(10);
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build();
    let result = match rt {
        Ok(rt) => rt.block_on(run(url, seconds, interval_ms)),
        Err(e) => Err(e.to_string()),
    };
    match result {
        Ok(line) => println!("{line}"),
        Err(e) => {
            eprintln!("opcua_latency: {e}");
            std::process::exit(1);
        }
    }
}
