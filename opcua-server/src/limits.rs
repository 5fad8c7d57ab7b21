//! What one OPC UA client may cost: sessions, subscriptions, monitored items, message and
//! request sizes. Defaults sized for a cell's MES, SCADA and an engineering client at once;
//! the stack answers past a limit with its status codes (`BadTooManySessions`,
//! `BadTooManyMonitoredItems`, `BadTcpMessageTooLarge`, …), and the scan never notices.

use opcua::server::ServerBuilder;

/// How often per logic tick the stack's subscriptions and the publisher look for work (1 ms at a
/// 10 ms tick, tokio's timer resolution). A subscription publishes at a poll once its interval
/// has elapsed since its last publish, and restarts its interval then: polled exactly at the
/// interval, jitter made every other publish wait a whole second interval (20 ms at 10 ms);
/// polled ten times a tick, a value waits at most a tenth of a tick for the publisher and a
/// publishing interval plus a tenth for its publish (`bench/scan_cost.py`: the publisher's stage
/// is a per-run phase, run medians 0.6–1.7 ms at five polls a tick, 0.6–0.7 ms at ten).
pub const POLLS_PER_TICK: u32 = 10;

/// The poll period in ms for a logic tick of `tick_ms` (at least 1 ms).
pub fn poll_ms(tick_ms: u32) -> u64 {
    u64::from(tick_ms.div_ceil(POLLS_PER_TICK).max(1))
}

/// The server's limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Sessions open at once.
    pub max_sessions: usize,
    /// Subscriptions per session.
    pub max_subscriptions_per_session: usize,
    /// Monitored items per subscription.
    pub max_monitored_items_per_sub: usize,
    /// Largest message (bytes), request or response.
    pub max_message_size: usize,
    /// Nodes per Read, Write or Browse request.
    pub max_nodes_per_request: usize,
    /// Values a monitored item queues between publishes (a client asking more gets this).
    pub max_item_queue: usize,
    /// Notification messages a subscription keeps waiting for the client's Publish requests.
    pub max_queued_notifications: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_sessions: 8,
            max_subscriptions_per_session: 4,
            max_monitored_items_per_sub: 5000,
            max_message_size: 4 << 20,
            max_nodes_per_request: 5000,
            // One second of ticks at 10 ms (async-opcua's 10 values, 100 ms, lost ticks whenever
            // a loaded machine delayed a publish longer).
            max_item_queue: 100,
            max_queued_notifications: 100,
        }
    }
}

impl Limits {
    /// Puts the limits and the tick-rate subscription intervals into `builder`.
    pub fn apply(&self, builder: &mut ServerBuilder, tick_ms: u32) {
        let l = builder.limits_mut();
        l.max_sessions = self.max_sessions;
        l.max_message_size = self.max_message_size;
        l.subscriptions.max_subscriptions_per_session = self.max_subscriptions_per_session;
        l.subscriptions.max_monitored_items_per_sub = self.max_monitored_items_per_sub;
        l.subscriptions.max_monitored_item_queue_size = self.max_item_queue;
        l.subscriptions.max_queued_notifications = self.max_queued_notifications;
        l.subscriptions.min_publishing_interval_ms = f64::from(tick_ms);
        l.subscriptions.min_sampling_interval_ms = f64::from(tick_ms);
        l.operational.max_nodes_per_read = self.max_nodes_per_request;
        l.operational.max_nodes_per_write = self.max_nodes_per_request;
        l.operational.max_nodes_per_browse = self.max_nodes_per_request;
        l.operational.max_monitored_items_per_call = self.max_monitored_items_per_sub;
        // Arrays in a request may be as long as the largest request the limits allow (plus one,
        // so that one item too many is refused with its status code, not a decoding error).
        l.max_array_length = self
            .max_nodes_per_request
            .max(self.max_monitored_items_per_sub)
            + 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_poll_is_a_tenth_of_the_tick_rounded_up_and_at_least_1_ms() {
        assert_eq!(poll_ms(10), 1);
        assert_eq!(poll_ms(2), 1);
        assert_eq!(poll_ms(25), 3);
        assert_eq!(poll_ms(100), 10);
        assert_eq!(poll_ms(0), 1);
    }
}
