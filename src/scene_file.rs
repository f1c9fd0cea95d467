//! Reading the TOML scene format (feature `scene-file`). Placeholder: the reader is being
//! written on another branch; this line only keeps `#![deny(missing_docs)]` from failing the build.
