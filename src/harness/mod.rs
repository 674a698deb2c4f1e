//! Running many meshers on many surfaces: the comparison table ([`compare`]) and the
//! demo ([`demo`]), the report of one run ([`report`]). They return data; only the command line prints.
pub mod compare;
pub mod demo;
pub mod demo_page;
pub mod report;
pub mod target;
