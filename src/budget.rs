//! The memory budget: every allocation whose size follows from input (degrees, image
//! sizes, ray counts, file headers) is compared with it before anything is allocated, so
//! that hostile or mistaken input gets a [`Error::MemoryBudget`] naming the bytes
//! instead of exhausting the machine.
//!
//! The budget is [`DEFAULT_BUDGET`] (4 GiB), or `PSH_MAX_MEMORY` (bytes, or with a
//! suffix `K`, `M`, `G`, `T`: powers of 1024), or what [`set_budget`] last set (the
//! command line's `--max-memory`).

use crate::error::{clip, Error, Result};
use std::sync::atomic::{AtomicU64, Ordering};

/// The budget without `PSH_MAX_MEMORY` or [`set_budget`]: 4 GiB.
pub const DEFAULT_BUDGET: u64 = 4 << 30;

/// 0: not set by [`set_budget`].
static OVERRIDE: AtomicU64 = AtomicU64::new(0);

/// A size in bytes from `text`: digits, optionally followed by `K`, `M`, `G` or `T`
/// (powers of 1024, case-insensitive, an optional `B` or `iB` after it).
pub fn parse_bytes(text: &str) -> Result<u64> {
    let t = text.trim();
    let bad = || {
        Error::invalid(
            "memory size",
            crate::error::clip(t),
            "expected bytes, or a number with K, M, G or T (powers of 1024), e.g. 8G",
        )
    };
    let upper = t.to_ascii_uppercase();
    let body = upper
        .strip_suffix("IB")
        .or_else(|| upper.strip_suffix('B'))
        .unwrap_or(&upper);
    let (digits, shift) = match body.chars().last() {
        Some('K') => (&body[..body.len() - 1], 10),
        Some('M') => (&body[..body.len() - 1], 20),
        Some('G') => (&body[..body.len() - 1], 30),
        Some('T') => (&body[..body.len() - 1], 40),
        _ => (body, 0),
    };
    let n: u64 = digits.trim().parse().map_err(|_| bad())?;
    n.checked_mul(1 << shift).filter(|&b| b > 0).ok_or_else(bad)
}

/// Sets the budget for the rest of the process (the command line's `--max-memory`).
pub fn set_budget(bytes: u64) {
    OVERRIDE.store(bytes, Ordering::Relaxed);
}

/// The budget in bytes: [`set_budget`]'s, else `PSH_MAX_MEMORY`'s, else
/// [`DEFAULT_BUDGET`]. Error: `PSH_MAX_MEMORY` set but not a size.
pub fn budget() -> Result<u64> {
    match OVERRIDE.load(Ordering::Relaxed) {
        0 => match std::env::var("PSH_MAX_MEMORY") {
            Ok(v) => parse_bytes(&v),
            Err(_) => Ok(DEFAULT_BUDGET),
        },
        b => Ok(b),
    }
}

/// Checks that `count` items of `item_bytes` bytes each (the factors of `count` given
/// separately, multiplied with overflow checks) fit in the budget; returns the number of
/// items. Error [`Error::MemoryBudget`] naming `what`, the bytes and the budget.
pub fn check(what: &str, factors: &[usize], item_bytes: usize) -> Result<usize> {
    let budget = budget()?;
    let count = factors.iter().try_fold(1usize, |n, &f| n.checked_mul(f));
    let bytes = count.and_then(|n| n.checked_mul(item_bytes));
    match (count, bytes) {
        (Some(n), Some(b)) if b as u64 <= budget => Ok(n),
        _ => Err(Error::MemoryBudget {
            what: clip(what),
            bytes: bytes.map(|b| b as u128).unwrap_or_else(|| {
                factors
                    .iter()
                    .fold(item_bytes as u128, |n, &f| n.saturating_mul(f as u128))
            }),
            budget,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_bytes("4096").unwrap(), 4096);
        assert_eq!(parse_bytes("8G").unwrap(), 8 << 30);
        assert_eq!(parse_bytes(" 512 MiB ").unwrap(), 512 << 20);
        assert_eq!(parse_bytes("2kb").unwrap(), 2048);
        for bad in ["", "G", "-1G", "1.5G", "0", "99999999999T", "12X"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn checks_name_the_bytes_and_overflow_saturates() {
        assert_eq!(check("a small table", &[3, 4], 8).unwrap(), 12);
        let e = check("a huge table", &[1 << 40, 1 << 40], 8).unwrap_err();
        match e {
            Error::MemoryBudget { what, bytes, .. } => {
                assert_eq!(what, "a huge table");
                assert_eq!(bytes, 8u128 << 80);
            }
            other => panic!("{other}"),
        }
        let msg = check("an image", &[100_000, 100_000, 4], 8)
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("320000000000 bytes") && msg.contains("PSH_MAX_MEMORY"),
            "{msg}"
        );
    }
}
