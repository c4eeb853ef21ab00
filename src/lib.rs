//! acuity: perceptual level-of-detail selection.
