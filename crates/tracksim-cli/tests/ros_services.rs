//! `/tracksim/set_paused` and `/tracksim/reset` (issue 42) called by a ros2-client service
//! client (Cyclone DDS mapping, as the node's servers) on loopback only, in DDS domain 142,
//! bounded in time: the pause stops the simulated clock (the session takes longer by the
//! pause), the reset restarts the session (counted), both answer `success`.

use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::{Context, Name, NodeName, NodeOptions, ServiceTypeName};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};
use tracksim::ros::services::{
    RESET, SERVICE_MAPPING, SET_PAUSED, SetBoolRequest, SetBoolResponse, TriggerRequest,
    TriggerResponse,
};
use tracksim::ros::{RosOptions, run_ros};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Sends `req` until a response comes (discovery may lose the first ones), at most `limit`.
fn call<Req: ros2_client::Message + Clone + 'static, Resp: ros2_client::Message + 'static>(
    client: &ros2_client::service::Client<Req, Resp>,
    req: Req,
    limit: Duration,
) -> Option<Resp> {
    let t0 = Instant::now();
    while t0.elapsed() < limit {
        if client.send_request(req.clone()).is_err() {
            std::thread::sleep(Duration::from_millis(100));
            continue;
        }
        let sent = Instant::now();
        while sent.elapsed() < Duration::from_millis(500) {
            if let Ok(Some((_, r))) = client.receive_response() {
                return Some(r);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    None
}

#[test]
fn pause_and_reset_are_served_on_loopback() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap();
    let stop: &'static AtomicBool = Box::leak(Box::new(AtomicBool::new(false)));
    let opts = RosOptions {
        fast: false,
        max_time: Some(3.0),
        domain_id: 142,
        play_commands: true,
        interrupt: Some(stop),
        ..RosOptions::default()
    };
    let session = std::thread::spawn(move || {
        let t0 = Instant::now();
        let r = run_ros(&sc, &opts, &mut |m| eprintln!("node: {m}"));
        (r.map(|s| (s.resets, s.duration())), t0.elapsed())
    });

    let dp = DomainParticipantBuilder::new(142)
        .with_only_networks(vec![std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST)])
        .build()
        .unwrap();
    let ctx = Context::from_domain_participant(dp).unwrap();
    let mut node = ctx
        .new_node(
            NodeName::new("/", "services_test").unwrap(),
            NodeOptions::new().enable_rosout(false),
        )
        .unwrap();
    let q = tracksim::ros::dds::service_qos();
    let pause = node
        .create_client::<SetBoolRequest, SetBoolResponse>(
            SERVICE_MAPPING,
            &Name::parse(SET_PAUSED).unwrap(),
            &ServiceTypeName::new("std_srvs", "SetBool"),
            q.clone(),
            q.clone(),
        )
        .unwrap();
    let reset = node
        .create_client::<TriggerRequest, TriggerResponse>(
            SERVICE_MAPPING,
            &Name::parse(RESET).unwrap(),
            &ServiceTypeName::new("std_srvs", "Trigger"),
            q.clone(),
            q,
        )
        .unwrap();
    let limit = Duration::from_secs(15);
    let r = call(&pause, SetBoolRequest { data: true }, limit);
    let r = r.unwrap_or_else(|| {
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        panic!("no answer from set_paused")
    });
    assert!(r.success && r.message.contains("paused"), "{r:?}");
    std::thread::sleep(Duration::from_millis(1500));
    let r = call(&pause, SetBoolRequest { data: false }, limit).expect("resumed");
    assert!(r.success && r.message.contains("resumed"), "{r:?}");
    let r = call(&reset, TriggerRequest::default(), limit).expect("reset answered");
    assert!(r.success && r.message.contains("reset"), "{r:?}");
    let (result, wall) = session.join().unwrap();
    let (resets, duration) = result.expect("the session ran");
    assert!(resets >= 1, "{resets}");
    assert!((duration - 3.0).abs() < 0.02, "{duration}");
    // 3 s paced, after a pause of 1.5 s and a reset: longer than 4.5 s of wall time.
    assert!(wall > Duration::from_millis(4500), "{wall:?}");
    assert!(wall < Duration::from_secs(60), "{wall:?}");
}
