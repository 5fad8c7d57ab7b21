//! The HMI's alarm lists (one machine-wide, one per process) with acknowledge.
//!
//! An alarm is listed from the tick its cause appears. **Acknowledge** clears the list: every
//! entry goes, and an alarm whose cause still holds comes back at once, marked acknowledged (so a
//! persisting cause is never hidden, and an acknowledged alarm that is raised again after its
//! cause had gone shows as new). An entry whose cause goes away stays listed, inactive, until it is
//! acknowledged: the operator sees every alarm that happened, even a short one.

use hmi::AlarmEntry;

/// One alarm list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AlarmList {
    entries: Vec<AlarmEntry>,
}

impl AlarmList {
    /// The listed alarms, oldest first.
    pub fn entries(&self) -> &[AlarmEntry] {
        &self.entries
    }

    /// The cause of `text` appeared at `tick` (again, when it is listed inactive).
    pub fn raise(&mut self, text: &str, tick: u64) {
        match self.entries.iter_mut().find(|e| e.text == text) {
            Some(e) if e.active => {}
            Some(e) => {
                e.active = true;
                e.acknowledged = false;
                e.tick = tick;
            }
            None => self.entries.push(AlarmEntry {
                text: text.to_string(),
                active: true,
                acknowledged: false,
                tick,
            }),
        }
    }

    /// The cause of `text` has gone; the entry stays until acknowledged (or goes now when it was
    /// acknowledged already).
    pub fn clear(&mut self, text: &str) {
        self.entries.retain_mut(|e| {
            if e.text == text {
                e.active = false;
                !e.acknowledged
            } else {
                true
            }
        });
    }

    /// Makes the list's active alarms exactly `active` (a level source such as the kernel's alarm
    /// list of a process), raising the new ones at `tick`.
    pub fn sync(&mut self, active: &[String], tick: u64) {
        let gone: Vec<String> = self
            .entries
            .iter()
            .filter(|e| e.active && !active.contains(&e.text))
            .map(|e| e.text.clone())
            .collect();
        for text in gone {
            self.clear(&text);
        }
        for text in active {
            self.raise(text, tick);
        }
    }

    /// Acknowledge: the inactive entries go, the active ones stay marked acknowledged.
    pub fn acknowledge(&mut self) {
        self.entries.retain_mut(|e| {
            e.acknowledged = true;
            e.active
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shown(l: &AlarmList) -> Vec<(String, bool, bool, u64)> {
        l.entries()
            .iter()
            .map(|e| (e.text.clone(), e.active, e.acknowledged, e.tick))
            .collect()
    }

    #[test]
    fn acknowledge_clears_gone_alarms_and_a_persisting_cause_comes_back_acknowledged() {
        let mut l = AlarmList::default();
        l.sync(&["estop".into(), "lube".into()], 5);
        l.sync(&["estop".into()], 9);
        assert_eq!(
            shown(&l),
            vec![
                ("estop".into(), true, false, 5),
                ("lube".into(), false, false, 5)
            ]
        );
        l.acknowledge();
        assert_eq!(shown(&l), vec![("estop".into(), true, true, 5)]);
        // Still active at the next publish: stays, acknowledged.
        l.sync(&["estop".into()], 12);
        assert_eq!(shown(&l), vec![("estop".into(), true, true, 5)]);
        // The cause goes: an acknowledged entry leaves at once.
        l.sync(&[], 20);
        assert_eq!(shown(&l), vec![]);
        // Raised again: new, unacknowledged, with its new tick.
        l.sync(&["estop".into()], 30);
        assert_eq!(shown(&l), vec![("estop".into(), true, false, 30)]);
    }

    #[test]
    fn an_event_alarm_raised_again_while_listed_inactive_is_new_again() {
        let mut l = AlarmList::default();
        l.raise("d0: timeout", 3);
        l.raise("d0: timeout", 4);
        l.clear("d0: timeout");
        assert_eq!(shown(&l), vec![("d0: timeout".into(), false, false, 3)]);
        l.raise("d0: timeout", 8);
        assert_eq!(shown(&l), vec![("d0: timeout".into(), true, false, 8)]);
        l.clear("d0: timeout");
        l.acknowledge();
        assert_eq!(shown(&l), vec![]);
    }
}
