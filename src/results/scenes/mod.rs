//! Scenes: one per figure or analytic result of the paper, each in its own folder with
//! its parameters, computation, key numbers, verdict (`mod.rs`) and rendering
//! (`render.rs`); see [`crate::results::scene::Scene`]. Registering a scene is one line below; the
//! command line, the book and the tests iterate the registry. No scene imports another.

use crate::results::scene::Entry;

macro_rules! registry {
    ($($module:ident :: $scene:ident),* $(,)?) => {
        $(pub mod $module;)*

        /// Every scene, in the book's order.
        pub fn all() -> &'static [&'static dyn Entry] {
            &[$(&$module::$scene),*]
        }
    };
}

registry! {
    spectrum::Spectrum,
    fig2::Fig2,
    restitution::RestitutionLaws,
    fig3abc::Fig3abc,
    fig3d::Fig3d,
    fig4::Fig4,
    fig5::Fig5,
    fig6::Fig6,
    energetic_map::EnergeticMap,
    fig9::Fig9,
    experiment::Experiment,
    stiffness_matching::StiffnessMatching,
    atlas::Atlas,
    basins::Basins,
    boundaries::Boundaries,
    work_precision::WorkPrecision,
    side_by_side::SideBySide,
}

/// Looks a scene up by name.
///
/// # Errors
/// [`crate::error::ParameterError`] for a name that is not a scene's, listing the names.
pub fn find(name: &str) -> Result<&'static dyn Entry, crate::error::ParameterError> {
    let all = all();
    all.iter()
        .copied()
        .find(|s| s.name() == name)
        .ok_or_else(|| {
            let names: Vec<&str> = all.iter().map(|s| s.name()).collect();
            crate::error::ParameterError::new(
                "scene NAME",
                name,
                &format!("one of {}", names.join(", ")),
            )
        })
}
