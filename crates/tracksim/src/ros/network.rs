//! Which network the node's DDS participant uses: by default only loopback (`127.0.0.1`),
//! like `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`: RustDDS then advertises only loopback
//! unicast locators, joins and sends multicast only on loopback (if `lo` has multicast
//! enabled), and announces itself to the well-known discovery ports of `127.0.0.1`, so peers on
//! this machine find it with or without multicast. RustDDS still binds its UDP sockets to the
//! wildcard address; no other host learns their locators, but a firewall is what closes them.

use std::net::{IpAddr, Ipv4Addr};

/// The interfaces the participant uses for discovery and data.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum NetworkRange {
    /// Loopback only (`127.0.0.1`): this machine.
    #[default]
    Localhost,
    /// The interfaces holding these addresses (e.g. a robot's LAN address).
    Interfaces(Vec<IpAddr>),
    /// Every interface (RustDDS's default): anyone on the networks reached can discover and
    /// drive the robot.
    Any,
}

impl NetworkRange {
    /// Parses `localhost`, `any` or a comma-separated list of interface addresses.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "localhost" | "local" => Ok(NetworkRange::Localhost),
            "any" | "all" => Ok(NetworkRange::Any),
            _ => s
                .split(',')
                .map(|a| {
                    a.trim()
                        .parse::<IpAddr>()
                        .map_err(|_| format!("{a:?} is not an IP address, `localhost` or `any`"))
                })
                .collect::<Result<Vec<_>, _>>()
                .map(NetworkRange::Interfaces),
        }
    }

    /// The interface addresses to restrict the participant to (`None`: every interface).
    pub fn only_networks(&self) -> Option<Vec<IpAddr>> {
        match self {
            NetworkRange::Localhost => Some(vec![IpAddr::V4(Ipv4Addr::LOCALHOST)]),
            NetworkRange::Interfaces(a) => Some(a.clone()),
            NetworkRange::Any => None,
        }
    }

    /// Whether only this machine is reached.
    pub fn is_local(&self) -> bool {
        match self {
            NetworkRange::Localhost => true,
            NetworkRange::Interfaces(a) => a.iter().all(IpAddr::is_loopback),
            NetworkRange::Any => false,
        }
    }
}

impl std::fmt::Display for NetworkRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NetworkRange::Localhost => f.write_str("localhost (127.0.0.1)"),
            NetworkRange::Any => f.write_str("every interface"),
            NetworkRange::Interfaces(a) => {
                let list: Vec<String> = a.iter().map(IpAddr::to_string).collect();
                write!(f, "interfaces {}", list.join(", "))
            }
        }
    }
}
