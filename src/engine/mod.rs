//! Time integration of the models: exact flows, certified switching and impacts.

pub mod built;
pub mod dopri5;
pub mod flow;
pub mod map;
pub mod rigid;
pub mod sim;
pub mod ticker;
pub mod two_basis;
