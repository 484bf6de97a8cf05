//! A drive family that exists only in the tests: a trivial text protocol over a byte line,
//! plugged in through the registry with no edit outside this folder (its code, its
//! dictionary `text.yaml`, and the one `Registry::with` line in the test). It proves the
//! family seam: a recipe runs on it, with the safe stop, through the same engine as SD2.
//!
//! The protocol, one line per telegram, CR-terminated:
//! `R 4` reads object 4 → `= 5999` (a decimal integer), `W 3 6000` writes → `ok`;
//! a refusal is `! CODE TEXT`.

use crate::support::{assert_has, control_words, InProcessRun};
mod text_access;
mod text_simulator;

use drivescript::bus::{Bus, SerialSettings};
use drivescript::dictionary::{Address, Dictionary};
use drivescript::family::{
    serial_line, DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened, Registry,
    SimulatedDevice,
};
use drivescript::link::{Direction, ExplainError, TelegramExplainer};
use drivescript::sim::SimConfig;
use std::path::PathBuf;
use std::sync::Arc;

pub struct TextFamily;

impl Family for TextFamily {
    fn info(&self) -> FamilyInfo {
        let parse = |text: &str| {
            text.trim()
                .parse::<u16>()
                .map(|i| Address::indexed(i, 0))
                .map_err(|_| "a text-family address is an object number".to_string().into())
        };
        FamilyInfo::new("text", "Test family: a trivial text protocol", parse)
            .dictionaries(&[drivescript::builtin_dictionary!(
                "text",
                "tests/integration/text_family/text.yaml"
            )])
            .serial(SerialSettings::with_baud(9600))
            .address_help("the node number")
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        let number = text
            .unwrap_or("1")
            .parse::<u32>()
            .map_err(|_| FamilyError::DriveAddress(format!("--address {text:?}: a number")))?;
        Ok(DriveAddress {
            number,
            shown: format!("node {number}"),
        })
    }
    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        Ok(Box::new(text_access::TextAccess::new(
            serial_line(bus, self.id())?,
            drive.number,
            options.reply_timeout,
            context,
        )))
    }
    fn simulator(&self, _drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        SimulatedDevice::bytes(text_simulator::TextSimulator::new(config))
    }
    fn explainer(&self, _dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(TextExplainer)
    }
}

/// The telegrams are text already: the explanation is the line itself.
struct TextExplainer;

impl TelegramExplainer for TextExplainer {
    fn summary(&mut self, _direction: Direction, bytes: &[u8]) -> String {
        String::from_utf8_lossy(bytes).trim().to_string()
    }
    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        Ok(format!("  line {}\n", String::from_utf8_lossy(bytes).trim()))
    }
    fn json(&mut self, bytes: &[u8]) -> (serde_json::Value, bool) {
        (
            serde_json::json!({ "line": String::from_utf8_lossy(bytes).trim() }),
            true,
        )
    }
}

#[test]
fn a_test_family_plugs_in_through_the_registry_and_runs_a_recipe() {
    let registry = Registry::builtin().with(Arc::new(TextFamily));
    let recipe = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/integration/text_family/recipe.yaml");
    let trace = std::env::temp_dir().join(format!("drivescript-text-family-{}.trace", std::process::id()));
    let mut run = InProcessRun::new(recipe);
    run.registry = registry;
    run.dictionary.name = "text".into();
    let (result, _, trace_text) = run.run_traced(
        &trace,
        0,
        &[
            "using the built-in simulated TEXT drive (node 1",
            "finally 1  ok    set speed_setpoint = 0 rpm (default finally)",
            "drive left in ready to switch on at 0 rpm",
            "PASSED",
        ],
    );
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
    // The trace reads the family's telegrams with the family's own explainer.
    assert_has(&trace_text, &["TX 57 20 33 20 33 30 30 30 0d  # W 3 3000"]);
    let _ = std::fs::remove_file(&trace);
}
