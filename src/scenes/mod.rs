//! Scenes: one per figure or analytic result of the paper. A scene takes its own parameter
//! struct (with the paper's values as `Default`), computes only what its result needs, and
//! returns plain serialisable data. Rendering lives in [`crate::render`]; the list of
//! scenes and the glue between the two is [`crate::catalog`].

pub mod fig2;
pub mod fig3abc;
pub mod fig3d;
pub mod fig4;
pub mod fig5;
pub mod spectrum;
pub mod work_precision;
