//! A fixed-capacity queue of timed 3-vectors, allocated once: what the merger keeps
//! of each stream. Pushing into a full queue hands back the oldest element.

use std::collections::VecDeque;

/// A time and three values.
pub(crate) type Timed = (f64, [f64; 3]);

/// Fixed capacity: never reallocates after construction.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Queue {
    items: VecDeque<Timed>,
    capacity: usize,
}

impl Queue {
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            items: VecDeque::with_capacity(capacity),
            capacity,
        }
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_full(&self) -> bool {
        self.items.len() >= self.capacity
    }

    /// Append; when full, the oldest element is removed first and returned.
    pub fn push(&mut self, v: Timed) -> Option<Timed> {
        let dropped = if self.is_full() {
            self.items.pop_front()
        } else {
            None
        };
        self.items.push_back(v);
        dropped
    }

    pub fn front(&self) -> Option<Timed> {
        self.items.front().copied()
    }

    pub fn pop_front(&mut self) -> Option<Timed> {
        self.items.pop_front()
    }

    pub fn get(&self, i: usize) -> Option<Timed> {
        self.items.get(i).copied()
    }

    pub fn iter(&self) -> impl Iterator<Item = Timed> + '_ {
        self.items.iter().copied()
    }

    /// Index of the last element with time ≤ `t` (elements are in time order).
    pub fn last_at_or_before(&self, t: f64) -> Option<usize> {
        self.items.partition_point(|e| e.0 <= t).checked_sub(1)
    }

    /// Drop elements older than the last one at or before `t` (it stays: it still
    /// brackets times after `t`).
    pub fn keep_from(&mut self, t: f64) {
        while self.items.len() >= 2 && self.items[1].0 <= t {
            self.items.pop_front();
        }
    }
}
