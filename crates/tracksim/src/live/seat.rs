//! The driver's seat of a live session: which connection drives, and the grace period a
//! dropped driver has to come back.
//!
//! The first page to connect takes the seat and is given a token (the page keeps it for the
//! tab and sends it back as `/ws?token=...` when it reconnects). When the driver's connection
//! closes (a reload, a network hiccup, a malformed frame), the seat is held for the driver
//! for the grace period: the robot stops meanwhile (the session applies a dead-man stop), a
//! page presenting the token takes the seat back, any other page watches. Once the grace has
//! passed, the seat is free: a watcher already connected, or the next page, takes it with a
//! new token; with no page connected at all, the session ends (the operator has gone).
//!
//! A session of several robots has a seat per robot, each with its own token and grace; a
//! driver who stops closes their seat ([`Seat::finish`]) and the others drive on.

use std::time::{Duration, Instant};

/// The default grace period a dropped driver has to reconnect, s.
pub const DEFAULT_RECONNECT_GRACE_S: f64 = 30.0;

/// What the seat says about the driver, for the state streamed to the pages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriverStatus {
    /// Whether a driver is connected now.
    pub connected: bool,
    /// While the seat is held for a dropped driver: the grace left, s.
    pub grace_left_s: Option<f64>,
    /// How many times a dropped driver came back.
    pub reconnects: u32,
    /// The driver has stopped (a seat of a session of several robots): nobody drives this
    /// robot any more.
    pub finished: bool,
}

/// The seat: the driving connection, its token, when it was lost.
#[derive(Debug)]
pub struct Seat {
    grace: Duration,
    driver: Option<u64>,
    token: String,
    lost_at: Option<Instant>,
    reconnects: u32,
    ever_driven: bool,
    finished: bool,
}

/// A fresh seat token: 128 bits from the operating system's random source, hex (as the
/// session's, [`super::access::SessionToken`]).
fn new_token() -> String {
    super::access::SessionToken::new().as_str().to_string()
}

impl Seat {
    /// An empty seat with a grace period of `grace_s` seconds (0: none; finite, >= 0).
    pub fn new(grace_s: f64) -> Seat {
        Seat {
            grace: Duration::from_secs_f64(grace_s.clamp(0.0, 86_400.0)),
            driver: None,
            token: new_token(),
            lost_at: None,
            reconnects: 0,
            ever_driven: false,
            finished: false,
        }
    }

    /// The grace period, s.
    pub fn grace_s(&self) -> f64 {
        self.grace.as_secs_f64()
    }

    fn held(&self) -> bool {
        self.lost_at.is_some_and(|t| t.elapsed() < self.grace)
    }

    /// Connection `id` (presenting `token`, if any) asks for the seat; returns the token if it
    /// now drives. A held seat goes only to the token; a free one to anybody.
    pub fn claim(&mut self, id: u64, token: Option<&str>) -> Option<String> {
        if self.finished {
            return None;
        }
        if self.driver.is_some() {
            return (self.driver == Some(id)).then(|| self.token.clone());
        }
        if self.held() {
            if token != Some(self.token.as_str()) {
                return None;
            }
            self.reconnects += 1;
        } else if self.ever_driven {
            self.token = new_token();
        }
        self.driver = Some(id);
        self.lost_at = None;
        self.ever_driven = true;
        Some(self.token.clone())
    }

    /// Whether connection `id` drives.
    pub fn drives(&self, id: u64) -> bool {
        self.driver == Some(id)
    }

    /// Connection `id` closed: if it drove, the seat is held for the grace period.
    pub fn leave(&mut self, id: u64) {
        if self.driver == Some(id) {
            self.driver = None;
            self.lost_at = Some(Instant::now());
        }
    }

    /// The driver stopped: the seat is closed (nobody drives this robot again).
    pub fn finish(&mut self) {
        self.driver = None;
        self.lost_at = None;
        self.finished = true;
    }

    /// Whether the seat was ever taken.
    pub fn ever_driven(&self) -> bool {
        self.ever_driven
    }

    /// The driver's status now.
    pub fn status(&self) -> DriverStatus {
        let grace_left_s = self
            .lost_at
            .filter(|_| self.driver.is_none())
            .map(|t| self.grace.saturating_sub(t.elapsed()).as_secs_f64())
            .filter(|g| *g > 0.0);
        DriverStatus {
            connected: self.driver.is_some(),
            grace_left_s,
            reconnects: self.reconnects,
            finished: self.finished,
        }
    }

    /// Whether the driver dropped and its grace has passed (the seat is free again).
    pub fn abandoned(&self) -> bool {
        self.driver.is_none() && self.lost_at.is_some() && !self.held()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_seat_goes_back_only_to_its_token() {
        let mut s = Seat::new(60.0);
        let token = s.claim(1, None).expect("first page drives");
        assert_eq!(s.claim(2, None), None, "second page watches");
        s.leave(1);
        assert!(!s.status().connected);
        assert!(s.status().grace_left_s.unwrap() > 59.0);
        assert_eq!(s.claim(3, None), None, "held for the driver");
        assert_eq!(s.claim(4, Some("wrong")), None);
        assert_eq!(s.claim(5, Some(&token)), Some(token.clone()));
        assert!(s.drives(5) && s.status().connected);
        assert_eq!(s.status().reconnects, 1);
        assert!(!s.abandoned());
    }

    #[test]
    fn after_the_grace_anybody_takes_a_new_token() {
        let mut s = Seat::new(0.0);
        let token = s.claim(1, None).unwrap();
        s.leave(1);
        assert!(s.abandoned());
        assert_eq!(s.status().grace_left_s, None);
        let t2 = s.claim(2, None).expect("free seat");
        assert_ne!(t2, token, "a new driver gets a new token");
        assert!(!s.abandoned());
        assert_eq!(token.len(), 32);
    }
}
