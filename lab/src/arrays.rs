//! Fixed-length arrays of scene files (`resolution`, `position`,
//! `rotation_deg`, ...): exactly `N` elements, so a stray extra element is
//! an error like a missing one (serde's `[T; N]` reads the first `N` and
//! ignores the rest).

use std::fmt;
use std::marker::PhantomData;

use serde::de::{Deserialize, Deserializer, Error, IgnoredAny, SeqAccess, Visitor};

/// `[T; N]` read from an array of exactly `N` elements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Exact<T, const N: usize>(pub [T; N]);

impl<T: Default + Copy, const N: usize> Default for Exact<T, N> {
    fn default() -> Self {
        Exact([T::default(); N])
    }
}

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_seq(ExactVisitor::<T, N>(PhantomData))
    }
}

struct ExactVisitor<T, const N: usize>(PhantomData<T>);

impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for ExactVisitor<T, N> {
    type Value = Exact<T, N>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "an array of exactly {N} elements")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut items = Vec::with_capacity(N);
        while items.len() < N {
            match seq.next_element()? {
                Some(x) => items.push(x),
                None => return Err(A::Error::invalid_length(items.len(), &self)),
            }
        }
        let mut len = N;
        while seq.next_element::<IgnoredAny>()?.is_some() {
            len += 1;
        }
        if len > N {
            return Err(A::Error::invalid_length(len, &self));
        }
        let array = items
            .try_into()
            .map_err(|v: Vec<T>| A::Error::invalid_length(v.len(), &self))?;
        Ok(Exact(array))
    }
}
