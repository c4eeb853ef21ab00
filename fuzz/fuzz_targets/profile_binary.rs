//! The binary profile decoder: `acuity::profile::binary::decode`.
//!
//! The input is decoded twice: as it is, and with its last eight bytes
//! replaced by the FNV-1a checksum of the rest, so that mutations get past
//! the checksum and reach the field decoding and validation.
#![no_main]

use acuity::profile::{Profile, binary};
use libfuzzer_sys::fuzz_target;

fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn check(bytes: &[u8]) {
    if let Ok(profile) = binary::decode(bytes) {
        // A decoded profile is valid and encodes again.
        profile.validate().expect("decoded profile validates");
        let _ = binary::encode(&profile).expect("decoded profile encodes");
    }
    let _ = Profile::from_bytes(bytes);
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if data.len() >= 8 {
        let mut fixed = data.to_vec();
        let body = fixed.len() - 8;
        let sum = fnv1a64(&fixed[..body]);
        fixed[body..].copy_from_slice(&sum.to_le_bytes());
        check(&fixed);
    }
});
