//! Running many meshers on many surfaces: the comparison table ([`compare`]) and the
//! demo ([`demo`]). They return data; only the command line prints.
pub mod compare;
pub mod demo;
