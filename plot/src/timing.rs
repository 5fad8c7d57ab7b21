//! The timing diagram of a trace: one lane per signal, bits as 0/1 steps, bytes as steps scaled to
//! the lane with their values written at each change.

use packets::Signal;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Chart, FAMILY};
use std::borrow::Borrow;

use trace::TickRecord;

/// Most value labels written per byte lane (a busy byte would otherwise bury the lane).
const MAX_LABELS: usize = 40;

/// One lane: its label and the value steps `(tick, value)`, the first at the window's start.
#[derive(Debug, Clone, PartialEq)]
pub struct Lane {
    /// Name shown at the left (`START_PB I0A3`).
    pub label: String,
    /// True for a byte signal.
    pub byte: bool,
    /// `(tick, value)` at the start and at every change.
    pub steps: Vec<(u64, u8)>,
}

/// A timing diagram over ticks `from..=to`.
#[derive(Debug, Clone, PartialEq)]
pub struct TimingDiagram {
    /// Title line.
    pub title: String,
    /// First tick shown.
    pub from: u64,
    /// Last tick shown.
    pub to: u64,
    /// The tick length (for the time axis in ms).
    pub tick_ms: u32,
    /// The lanes, top to bottom.
    pub lanes: Vec<Lane>,
}

impl TimingDiagram {
    /// The lanes of `signals` (with their `labels`) over `from..=to` (to the last record when
    /// `to` is None) of the trace with tick `tick_ms` whose `records` arrive one at a time: the
    /// image is rebuilt record by record (inputs, forced values, changed outputs) from tick 0, and
    /// reading stops past `to`. A record that cannot be read ends it with that error.
    pub fn new<R: Borrow<TickRecord>, E>(
        title: String,
        tick_ms: u32,
        records: impl IntoIterator<Item = Result<R, E>>,
        signals: &[(Signal, String)],
        from: u64,
        to: Option<u64>,
    ) -> Result<TimingDiagram, E> {
        let mut image = vec![0u8; packets::PACKETS_LEN];
        let mut lanes: Vec<Lane> = signals
            .iter()
            .map(|(s, label)| Lane {
                label: label.clone(),
                byte: s.bit().is_none(),
                steps: Vec::new(),
            })
            .collect();
        let mut started = false;
        let start = |image: &[u8], lanes: &mut Vec<Lane>| {
            for (lane, (s, _)) in lanes.iter_mut().zip(signals) {
                lane.steps.push((from, s.read(image)));
            }
        };
        let mut last = 0;
        for r in records {
            let r = r?;
            let r = r.borrow();
            if to.is_some_and(|to| r.t > to) {
                break;
            }
            last = r.t;
            // The window starts with the image at the end of tick `from`.
            if r.t > from && !started {
                start(&image, &mut lanes);
                started = true;
            }
            for (s, v) in r.inputs.iter().chain(&r.outputs).chain(&r.forced) {
                s.write(&mut image, *v);
            }
            if started {
                for (lane, (s, _)) in lanes.iter_mut().zip(signals) {
                    let v = s.read(&image);
                    if lane.steps.last().map(|&(_, last)| last) != Some(v) {
                        lane.steps.push((r.t, v));
                    }
                }
            }
        }
        if !started {
            start(&image, &mut lanes);
        }
        Ok(TimingDiagram {
            title,
            from,
            to: to.unwrap_or(last),
            tick_ms,
            lanes,
        })
    }
}

impl Chart for TimingDiagram {
    fn size(&self) -> (u32, u32) {
        (1000, 90 + 50 * self.lanes.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let n = self.lanes.len().max(1) as f64;
        let x_end = self.to.max(self.from + 1) as f64;
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FAMILY, 16))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(170)
            .build_cartesian_2d(self.from as f64..x_end, 0f64..2.0 * n)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .disable_y_axis()
            .x_desc(format!("tick ({} ms)", self.tick_ms))
            .x_label_formatter(&|x| format!("{}", *x as u64))
            .label_style((FAMILY, 12))
            .draw()
            .map_err(err)?;
        let colours = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];
        for (i, lane) in self.lanes.iter().enumerate() {
            let base = 2.0 * (n - 1.0 - i as f64) + 0.3;
            let height = |v: u8| {
                if lane.byte {
                    base + 1.3 * f64::from(v) / 255.0
                } else {
                    base + 1.3 * f64::from(v.min(1))
                }
            };
            let mut pts: Vec<(f64, f64)> = Vec::with_capacity(lane.steps.len() * 2 + 1);
            for &(t, v) in &lane.steps {
                if let Some(&(_, y)) = pts.last() {
                    pts.push((t as f64, y));
                }
                pts.push((t as f64, height(v)));
            }
            if let Some(&(_, y)) = pts.last() {
                pts.push((x_end, y));
            }
            let colour = colours[i % colours.len()];
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                .map_err(err)?;
            // The lane's name in the label area, level with the lane.
            let (_, py) = chart.backend_coord(&(self.from as f64, base + 0.5));
            root.draw(&Text::new(
                lane.label.clone(),
                (12, py),
                (FAMILY, 13).into_font().color(&colour),
            ))
            .map_err(err)?;
            if lane.byte {
                for &(t, v) in lane.steps.iter().take(MAX_LABELS) {
                    chart
                        .draw_series(std::iter::once(Text::new(
                            v.to_string(),
                            (t as f64, base + 1.45),
                            (FAMILY, 11).into_font(),
                        )))
                        .map_err(err)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn lanes_follow_inputs_outputs_and_forces_inside_the_window() {
        let trace = trace::Trace {
            part: None,
            tick_ms: 10,
            ticks: vec![
                TickRecord {
                    t: 0,
                    inputs: vec![(sig("I0A3"), 1)],
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 5,
                    inputs: vec![(sig("I0A3"), 0)],
                    outputs: vec![(sig("W14K0"), 80)],
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 9,
                    forced: vec![(sig("U4A0"), 1)],
                    positions: Vec::new(),
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 30,
                    inputs: vec![(sig("I0A3"), 1)],
                    ..TickRecord::default()
                },
            ],
        };
        let sigs = [
            (sig("I0A3"), "START".to_string()),
            (sig("W14K0"), "FOV".to_string()),
            (sig("U4A0"), "U4A0".to_string()),
        ];
        let records = trace.ticks.iter().map(Ok::<_, ()>);
        let d = TimingDiagram::new("t".into(), trace.tick_ms, records, &sigs, 2, Some(20))
            .expect("records");
        let steps: Vec<Vec<(u64, u8)>> = d.lanes.iter().map(|l| l.steps.clone()).collect();
        assert_eq!(
            steps,
            vec![
                vec![(2, 1), (5, 0)],
                vec![(2, 0), (5, 80)],
                vec![(2, 0), (9, 1)]
            ]
        );
    }
}
