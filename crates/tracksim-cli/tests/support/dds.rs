//! A ROS 2 node of a test on loopback only (its DDS discovery too), in a domain of its own.

use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::{Context, NodeName, NodeOptions};

/// A ROS 2 node named `name` in DDS domain `domain`, on loopback only; keep the context alive
/// with the node.
pub fn peer(domain: u16, name: &str) -> (Context, ros2_client::Node) {
    let dp = DomainParticipantBuilder::new(domain)
        .with_only_networks(vec![std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST)])
        .build()
        .unwrap();
    let ctx = Context::from_domain_participant(dp).unwrap();
    let node = ctx
        .new_node(
            NodeName::new("/", name).unwrap(),
            NodeOptions::new().enable_rosout(false),
        )
        .unwrap();
    (ctx, node)
}
