//! A message's definition and its schema text in the MCAP `ros2msg` convention (what rosbag2
//! writes): the type's `.msg` text, then for every type it depends on (directly or not, each
//! once, depth first) a line of 80 `=`, a line `MSG: pkg/Type` and that type's `.msg` text.
//! Field types are written in full (`geometry_msgs/Point position`), so no reader has to
//! resolve a short name.

use serde::Serialize;
use serde::de::DeserializeOwned;

/// One message type's `.msg` definition.
#[derive(Debug)]
pub struct MsgDef {
    /// `pkg/Type` (e.g. `nav_msgs/Odometry`).
    pub name: &'static str,
    /// The `.msg` text (fields and constants, one a line).
    pub text: &'static str,
    /// The message types its fields use.
    pub deps: &'static [&'static MsgDef],
}

impl MsgDef {
    /// The schema name in MCAP and rosbag2: `pkg/msg/Type`.
    pub fn schema_name(&self) -> String {
        match self.name.split_once('/') {
            Some((pkg, ty)) => format!("{pkg}/msg/{ty}"),
            None => self.name.to_string(),
        }
    }

    /// The `ros2msg` schema text: this type's text and every dependency's.
    pub fn schema_text(&self) -> String {
        let mut order: Vec<&'static MsgDef> = Vec::new();
        fn visit(d: &'static MsgDef, order: &mut Vec<&'static MsgDef>) {
            for dep in d.deps {
                if !order.iter().any(|o| o.name == dep.name) {
                    order.push(dep);
                    visit(dep, order);
                }
            }
        }
        for dep in self.deps {
            if !order.iter().any(|o| o.name == dep.name) {
                order.push(dep);
                visit(dep, &mut order);
            }
        }
        let mut text = self.text.trim_end().to_string();
        text.push('\n');
        for d in order {
            text.push_str(&"=".repeat(80));
            text.push_str("\nMSG: ");
            text.push_str(d.name);
            text.push('\n');
            text.push_str(d.text.trim_end());
            text.push('\n');
        }
        text
    }
}

/// A ROS 2 message type: CDR through serde and its definition.
pub trait RosMessage: Serialize + DeserializeOwned {
    /// Its definition.
    const DEF: &'static MsgDef;

    /// The schema name (`pkg/msg/Type`).
    fn schema_name() -> String {
        Self::DEF.schema_name()
    }

    /// The `ros2msg` schema text with every dependency.
    fn schema_text() -> String {
        Self::DEF.schema_text()
    }
}
