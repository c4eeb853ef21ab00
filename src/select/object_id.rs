//! [`ObjectId`], the handle of an object in a selector: a leaf, so that
//! [`Gaze`](crate::Gaze) can name the object the eyes pursue without
//! `camera` and `select` depending on each other. Re-exported as
//! `acuity::select::ObjectId` and `acuity::ObjectId`.

/// Handle of an object added to a [`Selector`].
///
/// An id stays valid until its object is removed, whatever else is added,
/// removed or changed meanwhile (objects are stored densely and moved when
/// others are removed; the id goes through a table of handles). After
/// [`Selector::remove_object`] the id is stale: methods that take it
/// return an error (the accessors [`Selector::selection`],
/// [`Selector::diagnostics`] and [`Selector::fade`] panic), also once its
/// table entry holds a new object, which gets a new generation (entries
/// are reused; a generation
/// repeats only after 2^32 reuses of one entry). Ids are not tied to their
/// selector: one from another selector may name an object of this one.
///
/// [`Selector`]: crate::Selector
/// [`Selector::remove_object`]: crate::Selector::remove_object
/// [`Selector::selection`]: crate::Selector::selection
/// [`Selector::diagnostics`]: crate::Selector::diagnostics
/// [`Selector::fade`]: crate::Selector::fade
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ObjectId {
    pub(super) index: u32,
    pub(super) generation: u32,
}
