//! The behaviour-switching state machine (Pierre 2022, section 3, Tables 1-2).
