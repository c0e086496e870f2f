//! Tests live in `tests/`; scenes in `scenes/`.
