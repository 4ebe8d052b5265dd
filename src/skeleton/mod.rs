//! skeleton (placeholder)
