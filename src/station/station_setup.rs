//! What the station runs with: the recipes given on its command line (loaded and checked
//! once at the start, so the page only ever names one by its place in the list) and every
//! option a run takes. Only data and the start-up check; the runs are [`super::Station`]'s.

use super::station_view::RecipeView;
use crate::family::Registry;
use crate::run::{RunError, RunOptions, RunPlan};
use crate::session::Prompt;
use std::path::PathBuf;

/// A recipe the page may start.
pub struct StationRecipe {
    pub path: PathBuf,
    pub name: String,
    pub planned: Option<std::time::Duration>,
    pub prompts: Vec<Prompt>,
}

pub struct StationSetup {
    pub registry: Registry,
    pub recipes: Vec<StationRecipe>,
    pub options: RunOptions,
}

impl StationSetup {
    /// Loads and checks each recipe as a run will (nothing is sent); the first one that
    /// fails refuses the station.
    pub fn new(registry: Registry, files: &[PathBuf], options: RunOptions) -> Result<Self, RunError> {
        let mut recipes = Vec::new();
        for path in files {
            let loaded = RunPlan::load_file(&registry, path, &options.set, &options.dictionary)?;
            recipes.push(StationRecipe {
                path: path.clone(),
                name: loaded.plan.name().to_string(),
                planned: loaded.plan.planned_time(),
                prompts: loaded.plan.prompts().into_iter().map(|(p, _)| p).collect(),
            });
        }
        Ok(StationSetup {
            registry,
            recipes,
            options,
        })
    }

    /// The recipes as the page lists them.
    pub fn recipe_views(&self) -> Vec<RecipeView> {
        self.recipes
            .iter()
            .map(|r| RecipeView {
                name: r.name.clone(),
                file: r
                    .path
                    .file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                planned_s: r.planned.map(|d| d.as_secs_f64()),
            })
            .collect()
    }

    /// The bench's name: `--unit station=…`, else the host's.
    pub fn station_name(&self) -> String {
        self.options
            .operator
            .identity()
            .station
            .or_else(|| std::env::var("HOSTNAME").ok().filter(|h| !h.is_empty()))
            .or_else(|| {
                std::fs::read_to_string("/etc/hostname")
                    .ok()
                    .map(|h| h.trim().to_string())
                    .filter(|h| !h.is_empty())
            })
            .unwrap_or_else(|| "this bench".into())
    }
}
