//! Whose fault an error is: the input's (an argument, or a scene, profile,
//! mesh, CSV or image that does not parse or breaks a rule) or the run's
//! (I/O mid-run, the renderer, a metric script). Shells map the answer to
//! their exit codes; the lab itself only raises typed errors.
//!
//! Apart from [`crate::error`] so that the leaf error module imports no
//! other module (the scene format and the commands import it).

use crate::error::InputError;
use crate::preprocess::PreprocessError;
use crate::scene::SceneError;
use crate::screen_size::ScreenSizeError;

/// Whether `cause` alone is of an input kind: [`InputError`], the scene
/// format's and the screen-size table's errors, unusable preprocess
/// arguments, the runtime's errors but I/O, the renderer's parse, mesh,
/// LOD-chain and settings errors, and images that do not decode.
pub fn is_input_kind(cause: &(dyn std::error::Error + 'static)) -> bool {
    if cause.is::<InputError>() || cause.is::<SceneError>() || cause.is::<ScreenSizeError>() {
        return true;
    }
    if let Some(e) = cause.downcast_ref::<acuity::Error>() {
        return !matches!(e, acuity::Error::Io { .. });
    }
    if let Some(e) = cause.downcast_ref::<acuity_render::Error>() {
        use acuity_render::Error as R;
        return matches!(
            e,
            R::Parse { .. } | R::InvalidMesh { .. } | R::LodChain { .. } | R::Settings { .. }
        );
    }
    if let Some(e) = cause.downcast_ref::<image::ImageError>() {
        return matches!(
            e,
            image::ImageError::Decoding(_) | image::ImageError::Unsupported(_)
        );
    }
    matches!(
        cause.downcast_ref::<PreprocessError>(),
        Some(PreprocessError::Usage(_))
    )
}

/// Whether any error along `e`'s cause chain is of an input kind
/// ([`is_input_kind`]).
pub fn blames_input(e: &anyhow::Error) -> bool {
    e.chain().any(is_input_kind)
}
