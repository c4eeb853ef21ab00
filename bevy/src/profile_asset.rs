//! Profiles as Bevy assets: [`AcuityProfile`] and its loader, which reads
//! the binary `.acp` form and JSON (`.acp.json`) with
//! [`acuity::Profile::from_bytes`].
//!
//! A file that does not decode or validate fails to load: Bevy reports it
//! as an [`AssetLoadFailedEvent<AcuityProfile>`](bevy::asset::AssetLoadFailedEvent)
//! message carrying a [`ProfileLoadError`], and the entities that use the
//! handle stay unregistered. Nothing panics on bad bytes.

use bevy::asset::io::Reader;
use bevy::asset::{Asset, AssetLoader, LoadContext};
use bevy::reflect::TypePath;

/// An acuity profile (what each coarser LOD of one mesh lacks, made
/// offline by `acuity preprocess`) held as a Bevy asset.
///
/// Load one with `asset_server.load("rock.acp")`, or make one in code
/// with `profiles.add(AcuityProfile(profile))`.
#[derive(Asset, TypePath, Clone, Debug)]
pub struct AcuityProfile(pub acuity::Profile);

/// Why a profile file did not load.
#[derive(Debug)]
pub enum ProfileLoadError {
    /// The asset source could not be read.
    Io(std::io::Error),
    /// The bytes are not a valid profile (the runtime's error names the
    /// field or byte at fault).
    Profile(acuity::Error),
    /// The file is larger than the runtime accepts
    /// ([`acuity::profile::MAX_FILE_BYTES`]).
    TooLarge {
        /// The file's size, bytes.
        bytes: u64,
    },
}

impl std::fmt::Display for ProfileLoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Io(e) => write!(f, "reading the profile: {e}"),
            Self::Profile(e) => write!(f, "{e}"),
            Self::TooLarge { bytes } => write!(
                f,
                "{bytes} bytes is more than a profile's {}",
                acuity::profile::MAX_FILE_BYTES
            ),
        }
    }
}

impl std::error::Error for ProfileLoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            Self::Profile(e) => Some(e),
            Self::TooLarge { .. } => None,
        }
    }
}

/// Loads [`AcuityProfile`]s from `.acp` (binary) and `.acp.json` files;
/// the contents decide the form (the binary magic bytes, else JSON), so a
/// binary file under the JSON name loads too.
#[derive(Default, TypePath)]
pub struct AcuityProfileLoader;

impl AssetLoader for AcuityProfileLoader {
    type Asset = AcuityProfile;
    type Settings = ();
    type Error = ProfileLoadError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        _load_context: &mut LoadContext<'_>,
    ) -> Result<AcuityProfile, ProfileLoadError> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(ProfileLoadError::Io)?;
        if bytes.len() as u64 > acuity::profile::MAX_FILE_BYTES {
            return Err(ProfileLoadError::TooLarge {
                bytes: bytes.len() as u64,
            });
        }
        acuity::Profile::from_bytes(&bytes)
            .map(AcuityProfile)
            .map_err(ProfileLoadError::Profile)
    }

    fn extensions(&self) -> &[&str] {
        &["acp", "acp.json"]
    }
}
