//! The web HMI in a real browser (Debian `chromium`, driven over the DevTools protocol: `cdp`):
//! the pages load without errors, a signal the sim changes changes on the page, a force set from
//! the page reaches the image and the recorded trace, the timing diagram draws; on the Machine
//! page of a part run, START moves the DRO and advances the block, FEED HOLD brings the path speed
//! to 0 and stops the DRO, RESET returns to the first block; the PLC messages are listed there and
//! "Acknowledge all" acknowledges them. A failing step
//! leaves a screenshot in `target/browser-failures/`. Without `/usr/bin/chromium` the test is
//! skipped with a loud message, except under `CI=true`, where it fails.
//! `HMI_SCREENSHOTS=DIR` keeps a screenshot of every page.

use crate::hmi_common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::cdp::{Browser, CHROMIUM};
use hmi_common::{Hmi, operator_lathe, root};

/// Polls `probe` every 50 ms until it returns `Some` or `secs` pass.
async fn until<T, F, Fut>(what: &str, secs: u64, mut probe: F) -> Result<T, String>
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = Option<T>>,
{
    let deadline = Instant::now() + Duration::from_secs(secs);
    loop {
        if let Some(v) = probe().await {
            return Ok(v);
        }
        if Instant::now() > deadline {
            return Err(format!("timed out waiting for {what}"));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

async fn js(c: &Browser, script: &str) -> Result<serde_json::Value, String> {
    c.js(script).await
}

async fn text(c: &Browser, css: &str) -> Option<String> {
    c.text(css).await
}

async fn shot(c: &Browser, dir: &Path, name: &str) {
    if let Ok(png) = c.screenshot().await {
        let _ = std::fs::create_dir_all(dir);
        let _ = std::fs::write(dir.join(format!("{name}.png")), png);
    }
}

async fn search(c: &Browser, q: &str) -> Result<(), String> {
    c.type_into("#search", q).await
}

/// Opens the page `name` with a click on its tab, until the tab is the active one (while the page
/// still lays out its header, a click can land on the neighbouring tab).
async fn page(c: &Browser, name: &str) -> Result<(), String> {
    let tab = format!("nav button[data-page={name}]");
    let active = format!("return document.querySelector('{tab}.active') !== null");
    for _ in 0..20 {
        c.click(&tab).await?;
        if c.js(&active).await? == serde_json::Value::Bool(true) {
            return Ok(());
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    Err(format!("the {name} tab did not become active"))
}

async fn steps(c: &Browser, hmi: &Hmi, keep: Option<&Path>) -> Result<(), String> {
    open_with_token(c, hmi).await?;
    until("the first live frame", 20, || async {
        text(c, "#status").await.filter(|t| t.starts_with("tick"))
    })
    .await?;
    // A signal the sim changes (I1K5: on from tick 155 to 600 of each 2000) changes on the page.
    search(c, "I1K5").await?;
    let seen = std::cell::RefCell::new(std::collections::BTreeSet::new());
    until("I1K5 to show both 0 and 1", 30, || async {
        if let Some(v) = text(c, "tr[data-signal=I1K5] .val").await {
            seen.borrow_mut().insert(v);
        }
        let s = seen.borrow();
        (s.contains("0") && s.contains("1")).then_some(())
    })
    .await?;
    // Force LUBE_LAMP (U5A2) from the page; the image shows it forced.
    search(c, "U5A2").await?;
    let row = "tr[data-signal=U5A2]";
    c.type_into(&format!("{row} input"), "1").await?;
    c.click(&format!("{row} button.force")).await?;
    until("U5A2 forced in the image", 10, || async {
        let v: serde_json::Value =
            serde_json::from_str(&hmi.http("GET", "/api/signal/U5A2", None).1).ok()?;
        (v["value"] == 1 && v["forced"] == true).then_some(())
    })
    .await?;
    until("the page's force marker", 5, || async {
        text(c, &format!("{row} .forced"))
            .await
            .filter(|t| t == "F=1")
    })
    .await?;
    if let Some(d) = keep {
        shot(c, d, "signals").await;
    }
    // Program page: source lines with live values.
    page(c, "program").await?;
    until("live values on the source", 5, || async {
        text(c, "#source")
            .await
            .filter(|t| t.contains("SPINDLE_CW") && t.contains("U4A0="))
    })
    .await?;
    // Power flow from the scan (`--hmi-flow`): line 62 (CHAIN_OK = ESTOP_PB_OK * OVERTRAVEL_OK)
    // computed 1 and is drawn energised.
    until("power flow on line 62", 5, || async {
        let v = js(
            c,
            "const e = [...document.querySelectorAll('#source .line')].find(e => e.querySelector('.ln').textContent === '62'); \
             return e ? [e.className, e.querySelector('.sv').textContent] : null",
        )
        .await
        .ok()?;
        let (class, vals) = (v[0].as_str()?, v[1].as_str()?);
        (class == "line on" && vals.starts_with("⇒ 1  ← ")).then_some(())
    })
    .await?;
    // The page's toggle switches power flow off at run time, and on again.
    for on in [false, true] {
        js(
            c,
            "document.getElementById('flow-toggle').click(); return null",
        )
        .await?;
        until("the power-flow toggle took effect", 15, || async {
            let v = js(
                c,
                "return [document.getElementById('flow-toggle').checked, (state.snap.flow || []).length, state.snap.flow_enabled]",
            )
            .await
            .ok()?;
            let n = v[1].as_u64()?;
            (v[0] == on && v[2] == on && (n > 0) == on).then_some(())
        })
        .await?;
    }
    if let Some(d) = keep {
        shot(c, d, "program").await;
    }
    // Trace page: the timing diagram draws.
    page(c, "trace").await?;
    js(c, "const e = document.getElementById('trace-signals'); e.value = 'I1K5,U5A2,U4A0,W14K0'; e.dispatchEvent(new Event('change'));").await?;
    until("samples on the timing diagram", 10, || async {
        let n = js(c, "return trace.ticks.length").await.ok()?;
        (n.as_u64()? > 20).then_some(())
    })
    .await?;
    let canvases = js(
        c,
        "return document.querySelectorAll('#chart canvas').length",
    )
    .await?;
    if canvases.as_u64() < Some(1) {
        return Err("uPlot drew no canvas".into());
    }
    if let Some(d) = keep {
        shot(c, d, "trace").await;
    }
    // Machine page: the status interface (overrides from the image, handshake counts).
    page(c, "machine").await?;
    until("process 1 on the Machine page", 5, || async {
        text(c, "#proc-1 .info")
            .await
            .filter(|t| t.contains("F 100%"))
    })
    .await?;
    if let Some(d) = keep {
        shot(c, d, "machine").await;
    }
    let errors = js(c, "return window.__errors").await?;
    if errors != serde_json::json!([]) {
        return Err(format!("errors on the page: {errors}"));
    }
    Ok(())
}

/// True when the browser is there; otherwise says so loudly (and fails under `CI=true`).
fn have_browser() -> bool {
    if Path::new(CHROMIUM).exists() {
        return true;
    }
    let msg = "!!! SKIPPED: the browser tests need Debian chromium \
               (apt-get install -y --no-install-recommends chromium) !!!";
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{msg}");
    eprintln!("{msg}");
    false
}

/// Opens the start URL (`/?token=…`): the server answers with the session cookie and sends the
/// browser to `/`, which then works with the cookie alone (the address no longer shows the token).
async fn open_with_token(c: &Browser, hmi: &Hmi) -> Result<(), String> {
    let token = hmi.token.as_deref().ok_or("the start URL has no token")?;
    c.goto(&format!("http://{}/?token={token}", hmi.addr))
        .await?;
    let url = c.url().await?;
    if url != format!("http://{}/", hmi.addr) {
        return Err(format!("the start URL did not lead to / but to {url}"));
    }
    // The cookie is HttpOnly: the page's scripts do not see it.
    let seen = js(c, "return document.cookie").await?;
    if seen.as_str().is_some_and(|s| s.contains("ncplc_hmi_")) {
        return Err(format!("the session cookie is readable by scripts: {seen}"));
    }
    Ok(())
}

/// Runs `steps` in a fresh browser against `hmi`; on failure keeps a screenshot named `name`
/// and panics with the step's error. Stops the HMI either way.
async fn in_browser<F>(hmi: Hmi, name: &str, steps: F)
where
    F: for<'a> FnOnce(
        &'a Browser,
        &'a Hmi,
        Option<&'a Path>,
    ) -> std::pin::Pin<
        Box<dyn std::future::Future<Output = Result<(), String>> + 'a>,
    >,
{
    let client = Browser::launch().await.expect("Chromium starts");
    let keep = std::env::var_os("HMI_SCREENSHOTS").map(PathBuf::from);
    let result = steps(&client, &hmi, keep.as_deref()).await;
    if let Err(e) = &result {
        let failures = root().join("target/browser-failures");
        shot(&client, &failures, name).await;
        drop(client);
        hmi.stop();
        panic!("{e} (screenshot: {}/{name}.png)", failures.display());
    }
    drop(client);
    hmi.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_pages_show_live_values_and_a_force_from_the_page_reaches_the_image_and_the_trace() {
    if !have_browser() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("browser.jsonl");
    let hmi = Hmi::start(
        &root().join("plc-programs/lathe"),
        &["--record", trace.to_str().expect("utf8"), "--hmi-flow"],
    );
    in_browser(hmi, "hmi", |c, h, keep| Box::pin(steps(c, h, keep))).await;
    let text = std::fs::read_to_string(&trace).expect("trace");
    assert!(
        text.lines().any(|l| l.contains(r#""forced":{"U5A2":1}"#)),
        "the page's force is in the trace"
    );
}

/// The DRO's command column of axes X and Z as the page shows them (read in one script: the
/// table's rows are replaced whenever a value changes).
async fn dro(c: &Browser) -> Option<(String, String)> {
    let v = js(
        c,
        "const t = a => document.querySelector('#proc-1 tr[data-axis=' + a + '] td.cmd'); \
         return t('X') && t('Z') ? [t('X').textContent, t('Z').textContent] : null",
    )
    .await
    .ok()?;
    Some((v[0].as_str()?.to_string(), v[1].as_str()?.to_string()))
}

async fn click(c: &Browser, css: &str) -> Result<(), String> {
    c.click(css).await
}

/// The block's N number as the page shows it (`N40 (4)`).
async fn block_n(c: &Browser) -> Option<u64> {
    let t = text(c, "#proc-1 .block").await?;
    t.strip_prefix('N')?.split(' ').next()?.parse().ok()
}

async fn machine_steps(c: &Browser, hmi: &Hmi, keep: Option<&Path>) -> Result<(), String> {
    open_with_token(c, hmi).await?;
    page(c, "machine").await?;
    until("PART1 selected, idle", 20, || async {
        let state = text(c, "#proc-1 .state").await?;
        let program = text(c, "#proc-1 .program").await?;
        (state == "idle" && program == "PART1").then_some(())
    })
    .await?;
    let at_rest = dro(c).await.ok_or("no DRO on the page")?;
    if at_rest != ("0.000".into(), "0.000".into()) {
        return Err(format!("the DRO before START: {at_rest:?}"));
    }
    click(c, "#proc-1 button.start").await?;
    until("the DRO moving in block N40 or later", 20, || async {
        let n = block_n(c).await?;
        let (x, z) = dro(c).await?;
        (n >= 40 && x != "0.000" && z != "0.000").then_some(())
    })
    .await?;
    let source = text(c, "#proc-1 .source").await.unwrap_or_default();
    if !source.starts_with('N') {
        return Err(format!("the block's source line: {source:?}"));
    }
    if let Some(d) = keep {
        shot(c, d, "machine-running").await;
    }
    click(c, "#proc-1 button.hold").await?;
    let held = until("the path speed 0 under FEED HOLD", 10, || async {
        let speed = text(c, "#proc-1 .speed").await?;
        let state = text(c, "#proc-1 .state").await?;
        (speed == "0.0" && state == "held").then_some(())
    })
    .await;
    held?;
    let stopped = dro(c).await.ok_or("no DRO")?;
    tokio::time::sleep(Duration::from_millis(300)).await;
    let later = dro(c).await.ok_or("no DRO")?;
    if later != stopped {
        return Err(format!(
            "the DRO moved under FEED HOLD: {stopped:?} → {later:?}"
        ));
    }
    // The tool path: the plan's 11 pieces and the sampled set points.
    let drawn = js(
        c,
        "const t = paths.get(1); return [t.programmed.length, t.actual.length > 5, document.querySelector('#proc-1 canvas.toolpath').hidden]",
    )
    .await?;
    if drawn != serde_json::json!([11, true, false]) {
        return Err(format!("tool path [pieces, sampled, hidden]: {drawn}"));
    }
    if let Some(d) = keep {
        shot(c, d, "machine-held").await;
    }
    click(c, "#proc-1 button.reset").await?;
    until("RESET back to the first block", 10, || async {
        let state = text(c, "#proc-1 .state").await?;
        let block = text(c, "#proc-1 .block").await?;
        (state == "idle" && block == "N10 (1)").then_some(())
    })
    .await?;
    // The modal codes of N10 G53 S1200 M03 with MEFI's G90, G94 and G40 from the start.
    until("the modal codes of N10", 10, || async {
        let modal = text(c, "#proc-1 .modal").await?;
        (modal == "G90 G94 G53 G40 S1200 M03").then_some(())
    })
    .await?;
    let errors = js(c, "return window.__errors").await?;
    if errors != serde_json::json!([]) {
        return Err(format!("errors on the page: {errors}"));
    }
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn start_and_feed_hold_on_the_machine_page_drive_the_simulated_lathe() {
    if !have_browser() {
        return;
    }
    let lathe = operator_lathe();
    let hmi = Hmi::start(lathe.path(), &["--program", "PART1"]);
    in_browser(hmi, "hmi-machine", |c, h, keep| {
        Box::pin(machine_steps(c, h, keep))
    })
    .await;
}

/// The Machine page lists the PLC's messages beside the machine alarms, and its "Acknowledge all"
/// acknowledges them (docs/plc-messages.md).
async fn message_steps(c: &Browser, hmi: &Hmi, _keep: Option<&Path>) -> Result<(), String> {
    open_with_token(c, hmi).await?;
    page(c, "machine").await?;
    let item = "#plc-messages li[data-number='1']";
    let shown = until("message 1 on the page", 20, || async {
        let t = text(c, item).await?;
        t.contains("P1 #1: Lubrication level low: refill the tank, then RESET (tick ")
            .then_some(t)
    })
    .await?;
    if shown.contains("acknowledged") {
        return Err(format!("acknowledged before the click: {shown}"));
    }
    let class = format!("return document.querySelector(\"{item}\").className");
    if js(c, &class).await? != serde_json::json!("active") {
        return Err("message 1 is not shown active".into());
    }
    click(c, "#ack-all").await?;
    until("message 1 acknowledged on the page", 10, || async {
        let t = text(c, item).await?;
        t.ends_with(", acknowledged)").then_some(())
    })
    .await?;
    if js(c, &class).await? != serde_json::json!("active acked") {
        return Err("message 1 is not shown active and acknowledged".into());
    }
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_machine_page_lists_the_plc_messages_and_acknowledges_them() {
    if !have_browser() {
        return;
    }
    let hmi = Hmi::start(&root().join("plc-programs/lathe"), &[]);
    // The lubrication level goes low (forced): message 1 follows 2 s later and stays.
    let (code, _) = hmi.http("POST", "/api/force", Some(r#"{"signal":"I0A7","value":0}"#));
    assert_eq!(code, 200);
    in_browser(hmi, "hmi-messages", |c, h, keep| {
        Box::pin(message_steps(c, h, keep))
    })
    .await;
}
