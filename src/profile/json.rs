//! The JSON profile encoding (feature `json`): the same fields as
//! [`Profile`], pretty-printed, keys in a fixed order. Floats are written
//! in their shortest round-tripping form, so reading and writing again
//! gives identical bytes.

use crate::error::{Error, Result};

use super::Profile;

/// Validates and encodes a profile as pretty-printed JSON, ending in a
/// newline.
pub fn encode(profile: &Profile) -> Result<Vec<u8>> {
    profile.validate()?;
    let mut bytes = serde_json::to_vec_pretty(profile).map_err(|e| Error::ProfileFormat {
        path: None,
        location: "output".into(),
        reason: e.to_string(),
    })?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Decodes and validates a JSON profile. Syntax errors give the line and
/// column; type errors also name the field. Anything but white space after
/// the document is an error (a profile with trailing bytes was not written
/// by [`encode`]).
pub fn decode(bytes: &[u8]) -> Result<Profile> {
    let de = &mut serde_json::Deserializer::from_slice(bytes);
    let profile: Profile = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let field = e.path().to_string();
        let inner = e.into_inner();
        let reason = if field == "." {
            inner.to_string()
        } else {
            format!("field `{field}`: {inner}")
        };
        Error::ProfileFormat {
            path: None,
            location: format!("line {}, column {}", inner.line(), inner.column()),
            reason,
        }
    })?;
    de.end().map_err(|e| Error::ProfileFormat {
        path: None,
        location: format!("line {}, column {}", e.line(), e.column()),
        reason: "unexpected bytes after the profile".into(),
    })?;
    profile.validate()?;
    Ok(profile)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::tests::sample_profile;

    #[test]
    fn round_trips_bit_identical() {
        let bytes = encode(&sample_profile()).unwrap();
        let back = decode(&bytes).unwrap();
        assert_eq!(back, sample_profile());
        assert_eq!(encode(&back).unwrap(), bytes);
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = encode(&sample_profile()).unwrap();
        for n in 0..bytes.len() - 1 {
            assert!(decode(&bytes[..n]).is_err(), "truncated at {n} decoded");
        }
    }

    #[test]
    fn overflowing_numbers_are_refused_with_the_field() {
        let text = String::from_utf8(encode(&sample_profile()).unwrap()).unwrap();
        let text = text.replacen("\"bounding_radius\": 1.0", "\"bounding_radius\": 1e39", 1);
        let e = decode(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("bounding_radius"), "{e}");
    }

    #[test]
    fn type_errors_name_field_and_line() {
        let text = String::from_utf8(encode(&sample_profile()).unwrap()).unwrap();
        let text = text.replacen("\"freq_cdiam\": 200.1", "\"freq_cdiam\": \"x\"", 1);
        let e = decode(text.as_bytes()).unwrap_err().to_string();
        assert!(
            e.contains("transitions[0].features[0].freq_cdiam") && e.contains("line"),
            "{e}"
        );
    }

    #[test]
    fn trailing_garbage_is_refused() {
        let mut bytes = encode(&sample_profile()).unwrap();
        bytes.extend_from_slice(b"GARBAGE\n");
        let e = decode(&bytes).unwrap_err().to_string();
        assert!(e.contains("after the profile"), "{e}");
        let mut bytes = encode(&sample_profile()).unwrap();
        bytes.extend_from_slice(b"  \n\t");
        decode(&bytes).unwrap();
    }
}
