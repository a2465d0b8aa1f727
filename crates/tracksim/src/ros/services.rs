//! The node's services (issue 42): `/tracksim/reset` (`std_srvs/Trigger`) and
//! `/tracksim/set_paused` (`std_srvs/SetBool`), on ros2-client's servers with the Cyclone DDS
//! request/reply mapping ([`SERVICE_MAPPING`]): the request and reply carry the request id
//! (client GUID, sequence number) in front of the payload, as `rmw_cyclonedds_cpp` does, on
//! `rq/tracksim/<name>Request` and `rr/tracksim/<name>Reply`. Read without waiting at sample
//! boundaries.

use super::dds::{DdsError, DdsNode};
use ros2_client::service::{Server, ServiceMapping};
use ros2_client::{Message, Name, ServiceTypeName};
use serde::{Deserialize, Serialize};

/// The request/reply mapping: Cyclone DDS's (`rmw_cyclonedds_cpp`).
pub const SERVICE_MAPPING: ServiceMapping = ServiceMapping::Cyclone;
/// The reset service's name.
pub const RESET: &str = "/tracksim/reset";
/// The pause service's name.
pub const SET_PAUSED: &str = "/tracksim/set_paused";

/// `std_srvs/Trigger` request (empty: IDL's placeholder byte).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriggerRequest {
    /// ROS 2's placeholder member of an empty structure.
    pub structure_needs_at_least_one_member: u8,
}
/// `std_srvs/Trigger` response.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriggerResponse {
    /// Whether it was done.
    pub success: bool,
    /// What was done, or why not.
    pub message: String,
}
/// `std_srvs/SetBool` request.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SetBoolRequest {
    /// The value.
    pub data: bool,
}
/// `std_srvs/SetBool` response (the same fields as Trigger's).
pub type SetBoolResponse = TriggerResponse;

impl Message for TriggerRequest {}
impl Message for TriggerResponse {}
impl Message for SetBoolRequest {}

/// A request taken in.
#[derive(Clone, Debug, PartialEq)]
pub enum ServiceCall {
    /// `reset`.
    Reset,
    /// `set_paused` with its value.
    SetPaused(bool),
}

/// The node's servers.
pub struct Services {
    reset: Server<TriggerRequest, TriggerResponse>,
    set_paused: Server<SetBoolRequest, SetBoolResponse>,
}

impl Services {
    /// Creates them on `node`.
    pub fn new(node: &mut DdsNode) -> Result<Self, DdsError> {
        let q = super::dds::service_qos();
        let n = node.node_mut();
        let name = |s: &str| Name::parse(s).map_err(|e| format!("service {s}: {e:?}"));
        let reset = n
            .create_server(
                SERVICE_MAPPING,
                &name(RESET)?,
                &ServiceTypeName::new("std_srvs", "Trigger"),
                q.clone(),
                q.clone(),
            )
            .map_err(|e| format!("service {RESET}: {e:?}"))?;
        let set_paused = n
            .create_server(
                SERVICE_MAPPING,
                &name(SET_PAUSED)?,
                &ServiceTypeName::new("std_srvs", "SetBool"),
                q.clone(),
                q,
            )
            .map_err(|e| format!("service {SET_PAUSED}: {e:?}"))?;
        Ok(Services { reset, set_paused })
    }

    /// Every request received since the last call, each answered by `answer` (whether it is
    /// done, and a message).
    pub fn serve(&self, answer: &mut dyn FnMut(&ServiceCall) -> (bool, String)) {
        for _ in 0..100 {
            let Ok(Some((id, _))) = self.reset.receive_request() else {
                break;
            };
            let (success, message) = answer(&ServiceCall::Reset);
            let _ = self
                .reset
                .send_response(id, TriggerResponse { success, message });
        }
        for _ in 0..100 {
            let Ok(Some((id, r))) = self.set_paused.receive_request() else {
                break;
            };
            let (success, message) = answer(&ServiceCall::SetPaused(r.data));
            let _ = self
                .set_paused
                .send_response(id, SetBoolResponse { success, message });
        }
    }
}
