//! Watching a learning environment live ([`Watch`]: the Python environments'
//! `render_mode="human"`): the drive page served on loopback by a [`Server`] over a watch-only
//! [`Hub`] (every page watches, nobody drives), fed the environment's state after each step in
//! the live session's format, optionally paced to the wall clock. The page is told it watches
//! (`/session.json` has `watch_only: true`; the states' `driver` is null): it shows no drive
//! controls and no driver's status, and its HUD shows what the learner commands (each belt's
//! speed and position, each flipper's target), the belts running in the 3-D view. An
//! environment that records nothing keeps no samples beyond the first: its states'
//! `forward_mps` (then the instantaneous speed along the heading, m/s) and `slip` are read from
//! the simulation, and `stall` is null (the page's own rule decides).
//!
//! Pacing: with a `speed` (simulated seconds per wall second, 1 = real time), [`Watch::show`]
//! sleeps until the wall clock has caught up with the episode's simulated time, so the robot
//! moves at that speed on the page and the training loop runs no faster; with `None` it
//! never waits (the page shows the states as they come, as fast as the learner steps).

use super::drive::{Feeds, state_value};
use super::hub::{DriveControl, Hub};
use super::server::{Mode, Server};
use crate::env::Env;
use crate::error::Result;
use crate::output::Scene;
use std::net::IpAddr;
use std::sync::Arc;
use std::time::Instant;

/// A learning environment's live page.
pub struct Watch {
    server: Server,
    hub: Arc<Hub>,
    feeds: Feeds,
    speed: Option<f64>,
    /// Wall clock and simulated time at the episode's first state.
    since: Option<(Instant, f64)>,
    /// The description of the scene the page has (a new episode may bring another).
    scene: String,
}

impl Watch {
    /// Serves the page of `env`'s scenario on `bind:port` (0: a free port); `speed` paces
    /// [`Watch::show`] (see the module's documentation).
    pub fn start(env: &Env, bind: IpAddr, port: u16, speed: Option<f64>) -> Result<Watch> {
        let hub = Hub::watch_only();
        let scene = Scene::new(env.scenario()).to_json();
        let server = Server::start(
            bind,
            port,
            Mode::Drive {
                hub: hub.clone(),
                scene_json: vec![scene.clone()],
            },
        )?;
        Ok(Watch {
            server,
            hub,
            feeds: Feeds::default(),
            speed,
            since: None,
            scene,
        })
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        self.server.url()
    }

    /// Open WebSocket connections (pages watching).
    pub fn connections(&self) -> u64 {
        self.hub.connections()
    }

    /// A new episode starts: its scene (if it differs: a randomised scenario) is what pages
    /// loaded from now on get, and pacing restarts.
    pub fn new_episode(&mut self, env: &Env) {
        let scene = Scene::new(env.scenario()).to_json();
        if scene != self.scene {
            self.hub.set_scene(scene.clone());
            self.scene = scene;
        }
        self.since = None;
        self.feeds.rut_seq = 0;
        self.hub.clear_ruts();
        self.feeds.hud.reset();
    }

    /// Publishes `env`'s state, after waiting for the wall clock when paced.
    pub fn show(&mut self, env: &Env) {
        let wait = self.wait(env.simulation().time());
        if !wait.is_zero() {
            std::thread::sleep(wait);
        }
        self.publish(env);
    }

    /// How long to wait before showing the state at simulated time `t`, s, when paced (zero
    /// otherwise; at most 10 s).
    pub fn wait(&mut self, t: f64) -> std::time::Duration {
        let (wall0, t0) = *self.since.get_or_insert((Instant::now(), t));
        let ahead = match self.speed {
            Some(speed) => (t - t0) / speed - wall0.elapsed().as_secs_f64(),
            None => 0.0,
        };
        std::time::Duration::from_secs_f64(ahead.clamp(0.0, 10.0))
    }

    /// Publishes `env`'s state now.
    pub fn publish(&mut self, env: &Env) {
        let sim = env.simulation();
        let control = DriveControl {
            forward_mps: 0.0,
            yaw_rate_rad_s: 0.0,
            flipper_angle_deg: (0..sim.flipper_names().len())
                .map(|i| Some(sim.flipper_target(i).to_degrees()))
                .collect(),
        };
        let mut state = state_value(
            env.runner(),
            &control,
            (self.speed.unwrap_or(0.0), &self.hub, None),
            None,
            &mut self.feeds,
        );
        if env.runner().view().samples.len() < 2 {
            // An environment that records nothing keeps no samples beyond the first, from
            // which a session's speed, slip and stall come (and a recording one has only its
            // first at the episode's start): the speed and the slip are the simulation's now (a
            // read: the physics is untouched), the stall is left to the page's own rule.
            let s = sim.sample();
            let p = &s.pose;
            let heading = [
                p.yaw.cos() * p.pitch.cos(),
                p.yaw.sin() * p.pitch.cos(),
                -p.pitch.sin(),
            ];
            let forward: f64 = (0..3).map(|k| s.linvel[k] * heading[k]).sum();
            state["forward_mps"] = serde_json::json!(forward);
            state["slip"] = serde_json::json!(s.slip);
            state["stall"] = serde_json::Value::Null;
            state["stall_since_s"] = serde_json::Value::Null;
        }
        self.hub.publish(state.to_string());
    }

    /// Stops serving (pages keep their last state).
    pub fn close(&mut self) {
        self.hub.request_stop();
        self.server.shutdown();
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        self.close();
    }
}
