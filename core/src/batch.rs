//! The one batch contract of the engines (docs/architecture.md, "Engine contract").
//!
//! Every engine's `push_batch(&[Sample])` returns a [`Batch`]: the estimates the
//! samples produced, how many samples were accepted, and the refused ones by index
//! and error. A batch is the same as pushing its samples one by one with `push`: a
//! refused sample changes nothing and the rest of the batch is still processed.
//!
//! All batch entry points go through one loop, [`each_released`]; [`run`] builds a
//! [`Batch`] with it, [`counted`] hands the estimates to a callback instead (the
//! `push_batch_with` forms: nothing is kept, so a clean batch allocates nothing).

/// A sample a batch push refused: its position in the batch (from 0) and why. The
/// other samples were processed as if pushed one by one; the refused one changed
/// nothing. Every engine's rejection type is this one with its own error
/// (`pace::Rejection`, `foot::FootRejection`, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct Rejected<E> {
    pub index: usize,
    pub error: E,
}

/// What a batch push produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch<T, E> {
    /// The estimates, in order (what `push` returned for each accepted sample that
    /// produced one; the step detector's are every step it released).
    pub estimates: Vec<T>,
    /// Samples accepted.
    pub accepted: usize,
    /// Samples refused, in batch order.
    pub rejected: Vec<Rejected<E>>,
}

impl<T, E> Default for Batch<T, E> {
    fn default() -> Self {
        Self {
            estimates: Vec::new(),
            accepted: 0,
            rejected: Vec::new(),
        }
    }
}

/// What a batch push whose estimates went to a callback did (the `push_batch_with`
/// forms): the counts, and the refused samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Counts<E> {
    /// Samples accepted.
    pub accepted: usize,
    /// Estimates handed to the callback.
    pub estimates: usize,
    /// Samples refused, in batch order.
    pub rejected: Vec<Rejected<E>>,
}

impl<E> Default for Counts<E> {
    fn default() -> Self {
        Self {
            accepted: 0,
            estimates: 0,
            rejected: Vec::new(),
        }
    }
}

/// Pushes `samples` in order with `push` (an engine's `push`) and collects what it
/// returned.
pub fn run<S, T, E>(samples: &[S], push: impl FnMut(&S) -> Result<Option<T>, E>) -> Batch<T, E> {
    let mut b = Batch::default();
    b.accepted = each(
        samples,
        |t| b.estimates.push(t),
        |r| b.rejected.push(r),
        push,
    );
    b
}

/// As [`run`], but every estimate goes to `on_estimate` instead of being kept.
pub fn counted<S, T, E>(
    samples: &[S],
    mut on_estimate: impl FnMut(&T),
    push: impl FnMut(&S) -> Result<Option<T>, E>,
) -> Counts<E> {
    let mut c = Counts::default();
    c.accepted = each(
        samples,
        |t| {
            c.estimates += 1;
            on_estimate(&t);
        },
        |r| c.rejected.push(r),
        push,
    );
    c
}

/// Pushes `samples` in order with `push`; each estimate goes to `on_estimate`, each
/// refused sample to `on_rejected`. Returns the number of samples accepted.
/// Allocates nothing itself. `samples` is any sequence: a slice (`push` gets `&S`),
/// or samples decoded on the fly (the bindings' packed buffers).
pub fn each<I: IntoIterator, T, E>(
    samples: I,
    mut on_estimate: impl FnMut(T),
    on_rejected: impl FnMut(Rejected<E>),
    mut push: impl FnMut(I::Item) -> Result<Option<T>, E>,
) -> usize {
    each_released(samples, &mut on_estimate, on_rejected, |s, emit| {
        if let Some(t) = push(s)? {
            emit(t);
        }
        Ok(())
    })
}

/// The batch loop itself, for an engine that can release several estimates per
/// sample (the step detector): `push` handles one sample and hands every estimate
/// it released to `emit` (`on_estimate`), in order. An `Err` refuses the sample
/// (`on_rejected` gets it with its index); `push` may still have emitted estimates
/// released earlier. Returns the number of samples accepted.
pub fn each_released<I: IntoIterator, T, E, F: FnMut(T)>(
    samples: I,
    mut on_estimate: F,
    mut on_rejected: impl FnMut(Rejected<E>),
    mut push: impl FnMut(I::Item, &mut F) -> Result<(), E>,
) -> usize {
    let mut accepted = 0;
    for (index, s) in samples.into_iter().enumerate() {
        match push(s, &mut on_estimate) {
            Ok(()) => accepted += 1,
            Err(error) => on_rejected(Rejected { index, error }),
        }
    }
    accepted
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Accepts even numbers, refuses odd ones, estimates every fourth.
    fn push(s: &u32) -> Result<Option<u32>, &'static str> {
        match s {
            s if s % 2 == 1 => Err("odd"),
            s if s % 4 == 0 => Ok(Some(s * 10)),
            _ => Ok(None),
        }
    }

    #[test]
    fn run_collects_estimates_counts_and_rejections() {
        let b = run(&[0, 1, 2, 3, 4, 6, 8], push);
        assert_eq!(b.estimates, vec![0, 40, 80]);
        assert_eq!(b.accepted, 5);
        assert_eq!(
            b.rejected,
            vec![
                Rejected {
                    index: 1,
                    error: "odd"
                },
                Rejected {
                    index: 3,
                    error: "odd"
                }
            ]
        );
        assert_eq!(run(&[], push), Batch::default());
    }

    #[test]
    fn counted_sees_the_same_estimates() {
        let samples = [0, 1, 2, 3, 4, 6, 8];
        let mut seen = Vec::new();
        let c = counted(&samples, |t| seen.push(*t), push);
        let b = run(&samples, push);
        assert_eq!(seen, b.estimates);
        assert_eq!(
            (c.accepted, c.estimates, c.rejected),
            (b.accepted, 3, b.rejected)
        );
    }

    #[test]
    fn several_estimates_per_sample_keep_their_order() {
        let mut out = Vec::new();
        let n = each_released(
            &[2u32, 3, 1],
            |t| out.push(t),
            |r: Rejected<()>| panic!("{r:?}"),
            |&s, emit| {
                (0..s).for_each(|i| emit(10 * s + i));
                Ok(())
            },
        );
        assert_eq!(n, 3);
        assert_eq!(out, vec![20, 21, 30, 31, 32, 10]);
    }
}
