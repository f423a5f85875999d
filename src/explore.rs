//! Placeholder (to be written).
