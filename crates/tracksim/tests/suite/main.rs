//! tracksim's integration tests, in one test binary. Each module was its own test target
//! (`tests/NAME.rs`); cargo builds and links every target against the whole library and
//! Rapier, so 44 targets cost most of CI's build time. Run one module with
//! `cargo test -p tracksim --test suite NAME::` (e.g. `golden::`).

#![warn(clippy::too_many_lines)]

mod common;
mod course_topics;

mod api_list;
mod bundled_scenarios;
mod flippers;
mod geometry;
mod golden;
mod issue_11_compliance;
mod issue_11_mass;
mod issue_11_parked_robot;
mod issue_11_position_independence;
mod issue_14_drawbar;
mod issue_14_motor;
mod issue_14_track_outputs;
mod issue_14_turning;
mod issue_15_loaders;
mod issue_16_clustered;
mod issue_16_line_tips;
mod issue_16_stabilization;
mod issue_16_top_run;
mod issue_17_conveyor;
mod issue_17_loop3d;
mod issue_17_paths3d;
mod issue_17_wheels;
mod issue_23_design_warnings;
mod issue_23_long_runs;
mod issue_23_origin_shift;
mod issue_23_traction_split;
mod issue_23_wheel_command;
mod issue_24_edge_checks;
mod issue_24_structure;
mod issue_25_env_sensors;
mod issue_25_sensors;
mod issue_26_urdf;
mod issue_27_mcap;
mod issue_28_course;
mod issue_29_env;
mod issue_30_soil;
mod issue_38_loads;
mod issue_38_order;
mod issue_38_pulley_order;
mod issue_38_soil;
mod issue_38_soil_balance;
mod issue_39_session;
mod issue_40_drive;
mod issue_40_team;
mod issue_41_camera;
mod issue_41_frames;
mod issue_41_video;
mod issue_42_import;
mod issue_42_ros_outputs;
mod issue_42_sdf;
mod issue_42_tracks_on_flippers;
mod issue_42_urdf_as_found;
mod issue_43_school;
mod issue_43_slip;
mod issue_43_team_reset;
mod issue_44_cull;
mod issue_45_inputs;
mod issue_45_servers;
mod issue_58_accuracy;
mod issue_59_no_stop_loses;
mod issue_60_absolem;
mod issue_62_margins;
mod layers;
mod live;
mod methods;
mod module_graph;
mod packbot_flat;
mod plates;
mod randomize;
mod scenario_immutable;
mod slope;
mod step_climb;
mod stepping_api;
mod team_attempts_review;
mod team_ensemble;
mod team_randomize;
mod terrain;
mod validation;
