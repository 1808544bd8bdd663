//! Bin sizes: how vvvv cuts one spread into several (a spread of vectors
//! flattened to values, the rows of a grid) for nodes that work per bin.
//!
//! A Bin Size pin is itself a spread, read in turn and wrapping until the
//! input is used up: sizes 2, 3 over 10 slices give bins of 2, 3, 2, 3. A size
//! of 0 is an empty bin; a negative first size -k divides the whole input into
//! k bins of (nearly) equal size, so the default -1 is "the whole spread".

use std::ops::Range;

use spreadlight_graph::{EvalContext, In, NodeError};

use super::MAX_SLICES;

/// The ranges of the bins that `sizes` cut a spread of `len` slices into.
/// Empty sizes give no bins. The last bin may be shorter than its size.
pub(crate) fn partition(len: usize, sizes: &[i64]) -> Vec<Range<usize>> {
    let Some(&first) = sizes.first() else {
        return Vec::new();
    };
    if first < 0 {
        let k = usize::try_from(first.unsigned_abs())
            .unwrap_or(usize::MAX)
            .min(len.max(1));
        // Bin j covers [j * len / k, (j + 1) * len / k): sizes differ by at most one.
        return (0..k).map(|j| j * len / k..(j + 1) * len / k).collect();
    }
    let mut bins = Vec::new();
    let (mut pos, mut round_start) = (0, 0);
    for (i, &size) in sizes.iter().cycle().enumerate() {
        let new_round = i > 0 && i % sizes.len() == 0;
        // The first round reads every size; later ones stop once the input is used up,
        // or when a whole round of (zero) sizes used nothing.
        if i >= sizes.len() && (pos >= len || (new_round && pos == round_start)) {
            break;
        }
        if new_round {
            round_start = pos;
        }
        let size = usize::try_from(size.max(0)).unwrap_or(usize::MAX);
        let end = pos.saturating_add(size).min(len);
        bins.push(pos..end);
        pos = end;
    }
    bins
}

/// The bins of input `data` cut by the Int pin `pin`, checked against [`MAX_SLICES`] bins.
pub(crate) fn bins_of(
    cx: &EvalContext<'_>,
    len: usize,
    pin: In<i64>,
) -> Result<Vec<Range<usize>>, NodeError> {
    let sizes = cx.get(pin)?;
    if sizes.len() > MAX_SLICES {
        return Err(cx.error(pin, format!("more than {MAX_SLICES} bin sizes")));
    }
    Ok(partition(len, sizes))
}

#[cfg(test)]
mod tests {
    use super::partition;

    #[test]
    fn sizes_wrap_until_the_input_is_used_up() {
        assert_eq!(partition(10, &[2, 3]), vec![0..2, 2..5, 5..7, 7..10]);
        assert_eq!(partition(5, &[2]), vec![0..2, 2..4, 4..5]);
        assert_eq!(
            partition(4, &[1, 0]),
            vec![0..1, 1..1, 1..2, 2..2, 2..3, 3..3, 3..4]
        );
        assert_eq!(partition(6, &[4, 4, 4]), vec![0..4, 4..6, 6..6]);
    }

    #[test]
    fn negative_first_size_divides_evenly() {
        assert_eq!(partition(6, &[-1]), vec![0..6]);
        assert_eq!(partition(6, &[-2]), vec![0..3, 3..6]);
        assert_eq!(partition(5, &[-2]), vec![0..2, 2..5]);
        assert_eq!(partition(0, &[-1]), vec![0..0]);
    }

    #[test]
    fn degenerate_sizes_terminate() {
        assert_eq!(partition(3, &[0]), vec![0..0]);
        assert_eq!(partition(3, &[0, 0]), vec![0..0, 0..0]);
        assert_eq!(partition(0, &[2]), vec![0..0]);
        assert!(partition(3, &[]).is_empty());
        assert_eq!(partition(2, &[i64::MAX]), vec![0..2]);
    }
}
