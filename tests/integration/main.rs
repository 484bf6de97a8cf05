//! The one integration test binary: golden vectors, the command line end to end, the
//! data-driven recipe cases under `tests/cases/`, Rhai scripts, and the report writers.

// As in the library: errors carry structured context and travel on cold paths.
#![allow(clippy::result_large_err)]

mod bench_limits;
mod bounded;
mod brake_first;
mod canopen;
mod canopen_types;
mod canopen_wide_integers;
mod capture_round_trip;
mod command_line;
mod ct_ansi;
mod decode_cli;
mod drive_sim;
mod editor;
mod eds_python;
mod emergencies;
mod end_to_end;
mod examples;
mod fault_campaign;
mod help_pages;
mod hints;
mod history;
mod history_keys;
mod history_wear;
mod hostile_files;
mod inverter_units;
mod language_server;
mod late_replies;
mod lenze_931;
mod lenze_931_maintain;
mod lenze_9400;
mod live_run;
mod loader_limits;
mod manual;
mod modbus;
mod modbus_pymodbus;
mod multi_drive;
mod operator;
mod operator_attempts;
mod outputs;
mod parameters;
mod quality_results;
mod recipe_cases;
mod recipe_schema;
mod replay;
mod reports;
mod results_integrity;
mod results_kill_campaign;
mod results_store;
mod run_pipeline;
mod safety;
mod scripts;
mod several_files;
mod sim_settings;
mod socketcan;
mod stop_command;
mod support;
mod text_family;
mod trace_decode;
mod trend_page;
mod vectors;
mod verdict_rule;
mod write_limits;
mod write_refusals;
