//! From a height image to blobs: the threshold at the cut height, a 3×3 opening, connected
//! components (4-neighbours, union-find over each row's runs of pixels), and the growth of given
//! instance labels into the mask.

use std::collections::VecDeque;

/// A row-major boolean image.
#[derive(Clone, Debug, PartialEq)]
pub struct Mask {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `true` where set.
    pub set: Vec<bool>,
}

/// The 4-neighbours of pixel `i` in a row-major image `width` pixels wide and `height` rows high:
/// left, right, above, below, each when inside the image.
pub fn four_neighbours(i: usize, width: usize, height: usize) -> impl Iterator<Item = usize> {
    let (u, v) = (i % width, i / width);
    [
        (u > 0).then(|| i - 1),
        (u + 1 < width).then(|| i + 1),
        (v > 0).then(|| i - width),
        (v + 1 < height).then(|| i + width),
    ]
    .into_iter()
    .flatten()
}

impl Mask {
    /// Whether pixel `(u, v)` is set; `false` outside the image.
    #[cfg(test)]
    fn at(&self, u: isize, v: isize) -> bool {
        u >= 0
            && v >= 0
            && (u as usize) < self.width
            && (v as usize) < self.height
            && self.set[v as usize * self.width + u as usize]
    }

    /// Whether pixel `i` and its eight neighbours are all set: whether `i` survives the 3×3
    /// erosion (outside the image counts as unset).
    fn interior(&self, i: usize) -> bool {
        let (w, u, v) = (self.width, i % self.width, i / self.width);
        u > 0
            && v > 0
            && u + 1 < w
            && v + 1 < self.height
            && [i - w, i, i + w]
                .iter()
                .all(|&c| self.set[c - 1] && self.set[c] && self.set[c + 1])
    }

    /// The components of the mask that keep a pixel under the 3×3 opening, whole (the opening by
    /// reconstruction): specks go, and sharp corners keep their tips. Also their labels, as
    /// [`components`] numbers them (0 for the pixels dropped).
    ///
    /// The opening is the union of the 3×3 windows of the pixels that survive the erosion, and each
    /// such window lies in its centre's component; so a component keeps a pixel under the opening
    /// exactly when one of its pixels survives the erosion, which is what is tested.
    pub fn without_specks(&self) -> (Mask, Vec<u32>) {
        let (mut parts, count) = components(self);
        let mut keep = vec![false; count as usize + 1];
        for (i, &part) in parts.iter().enumerate() {
            if part != 0 && !keep[part as usize] && self.interior(i) {
                keep[part as usize] = true;
            }
        }
        let set = parts
            .iter_mut()
            .map(|part| {
                if !keep[*part as usize] {
                    *part = 0;
                }
                *part != 0
            })
            .collect();
        (Mask { set, ..*self }, parts)
    }
}

/// A blob's pixels as a bitmap over their box, with a pixel of margin.
pub struct Window {
    u0: isize,
    v0: isize,
    columns: isize,
    rows: isize,
    set: Vec<bool>,
}

impl Window {
    /// The bitmap of `pixels` (indices into rows of `width`).
    pub fn around(pixels: &[usize], width: usize) -> Self {
        let (mut lo, mut hi) = ((isize::MAX, isize::MAX), (isize::MIN, isize::MIN));
        for &i in pixels {
            let (u, v) = ((i % width) as isize, (i / width) as isize);
            lo = (lo.0.min(u), lo.1.min(v));
            hi = (hi.0.max(u), hi.1.max(v));
        }
        let (u0, v0) = (lo.0 - 1, lo.1 - 1);
        let (columns, rows) = ((hi.0 - u0 + 2).max(0), (hi.1 - v0 + 2).max(0));
        let mut set = vec![false; (columns * rows) as usize];
        for &i in pixels {
            let (u, v) = ((i % width) as isize, (i / width) as isize);
            set[((v - v0) * columns + u - u0) as usize] = true;
        }
        Self {
            u0,
            v0,
            columns,
            rows,
            set,
        }
    }

    /// The pixels `(u, v)` of the box, its margin included, whose 3×3 window holds at least 5 of
    /// the blob's pixels: the blob's 3×3 median. Counted with running sums, row then column.
    pub fn median(&self) -> Vec<(isize, isize)> {
        let (columns, rows) = (self.columns as usize, self.rows as usize);
        let at = |x: usize, y: usize| u8::from(self.set[y * columns + x]);
        // Each cell's count over its row's three cells, then over three such rows.
        let mut across = vec![0_u8; columns * rows];
        for y in 0..rows {
            for x in 0..columns {
                let left = if x > 0 { at(x - 1, y) } else { 0 };
                let right = if x + 1 < columns { at(x + 1, y) } else { 0 };
                across[y * columns + x] = left + at(x, y) + right;
            }
        }
        let mut kept = Vec::new();
        for y in 0..rows {
            for x in 0..columns {
                let up = if y > 0 {
                    across[(y - 1) * columns + x]
                } else {
                    0
                };
                let down = if y + 1 < rows {
                    across[(y + 1) * columns + x]
                } else {
                    0
                };
                if up + across[y * columns + x] + down >= 5 {
                    kept.push((self.u0 + x as isize, self.v0 + y as isize));
                }
            }
        }
        kept
    }

    /// The box's columns and rows, its margin included.
    pub fn size(&self) -> (usize, usize) {
        (self.columns as usize, self.rows as usize)
    }

    /// The blob's bitmap as a mask over the box (row-major, [`Window::size`]).
    pub fn mask(&self) -> Mask {
        let (width, height) = self.size();
        Mask {
            width,
            height,
            set: self.set.clone(),
        }
    }

    /// The box's index of the image's pixel `i` (rows of `width`), a pixel within the box.
    pub fn local(&self, i: usize, width: usize) -> usize {
        let (u, v) = ((i % width) as isize, (i / width) as isize);
        ((v - self.v0) * self.columns + u - self.u0) as usize
    }

    /// The image's index (rows of `width`) of the box's pixel `j`; `None` for a pixel of the
    /// margin left of or above the image.
    pub fn image_index(&self, j: usize, width: usize) -> Option<usize> {
        let (x, y) = ((j as isize) % self.columns, (j as isize) / self.columns);
        let (u, v) = (self.u0 + x, self.v0 + y);
        (u >= 0 && v >= 0 && (u as usize) < width).then(|| v as usize * width + u as usize)
    }

    /// Whether pixel `(u, v)` is one of the blob's.
    pub fn holds(&self, u: isize, v: isize) -> bool {
        let (x, y) = (u - self.u0, v - self.v0);
        x >= 0
            && y >= 0
            && x < self.columns
            && y < self.rows
            && self.set[(y * self.columns + x) as usize]
    }
}

/// Disjoint sets over indices (of runs of pixels), with path halving.
struct Sets(Vec<u32>);

impl Sets {
    fn find(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let parent = self.0[self.0[i as usize] as usize];
            self.0[i as usize] = parent;
            i = parent;
        }
        i
    }

    fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            let (low, high) = (a.min(b), a.max(b));
            self.0[high as usize] = low;
        }
    }
}

/// Connected components of the set pixels, 4-neighbours: per pixel 0 for unset, else `1..=count`
/// numbered in the raster order of each component's first pixel; and the count.
pub fn components(mask: &Mask) -> (Vec<u32>, u32) {
    let width = mask.width;
    // The runs of set pixels, row by row: `(first pixel, one past the last)`; the runs of row `v`
    // are `runs[rows[v]..rows[v + 1]]`. Runs of consecutive rows that share a column touch.
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut rows = vec![0_usize];
    for (v, line) in mask.set.chunks(width.max(1)).enumerate() {
        let mut u = 0;
        while u < line.len() {
            if line[u] {
                let end = u + line[u..].iter().take_while(|&&set| set).count();
                runs.push((v * width + u, v * width + end));
                u = end;
            } else {
                u += 1;
            }
        }
        rows.push(runs.len());
    }
    let mut sets = Sets((0..runs.len() as u32).collect());
    for v in 1..rows.len().saturating_sub(1) {
        let (above, here) = (rows[v - 1]..rows[v], rows[v]..rows[v + 1]);
        let mut a = above.start;
        for r in here {
            let (start, end) = (runs[r].0 - width, runs[r].1 - width);
            // The runs above that end before this one starts touch no later run of this row.
            while a < above.end && runs[a].1 <= start {
                a += 1;
            }
            let mut k = a;
            while k < above.end && runs[k].0 < end {
                sets.join(r as u32, k as u32);
                k += 1;
            }
        }
    }
    let mut names = vec![0_u32; runs.len()];
    let mut count = 0;
    let mut out = vec![0_u32; mask.set.len()];
    for (r, &(start, end)) in runs.iter().enumerate() {
        let root = sets.find(r as u32) as usize;
        if names[root] == 0 {
            count += 1;
            names[root] = count;
        }
        out[start..end].fill(names[root]);
    }
    (out, count)
}

/// Each set pixel of `mask` takes the label of the nearest labelled set pixel, nearest in steps
/// through set pixels (4-neighbours, ties to the label reached first); set pixels that no label
/// reaches get 0. So a label eroded by a few pixels still claims its whole blob, and two labels
/// split a blob that the depth alone would merge.
pub fn grow_labels(mask: &Mask, labels: &[u32]) -> Vec<u32> {
    let width = mask.width;
    let mut out = vec![0_u32; mask.set.len()];
    let mut queue = VecDeque::new();
    for (i, (&set, &label)) in mask.set.iter().zip(labels).enumerate() {
        if set && label != 0 {
            out[i] = label;
            queue.push_back(i);
        }
    }
    while let Some(i) = queue.pop_front() {
        for j in four_neighbours(i, width, mask.height) {
            if mask.set[j] && out[j] == 0 {
                out[j] = out[i];
                queue.push_back(j);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SeededRng;

    /// The components by flood fill from each unvisited set pixel, in raster order: the oracle.
    fn flood(mask: &Mask) -> Vec<u32> {
        let mut out = vec![0_u32; mask.set.len()];
        let mut count = 0;
        for start in 0..mask.set.len() {
            if !mask.set[start] || out[start] != 0 {
                continue;
            }
            count += 1;
            let mut stack = vec![start];
            out[start] = count;
            while let Some(i) = stack.pop() {
                let (u, v) = ((i % mask.width) as isize, (i / mask.width) as isize);
                for (du, dv) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                    if mask.at(u + du, v + dv) {
                        let j = (v + dv) as usize * mask.width + (u + du) as usize;
                        if out[j] == 0 {
                            out[j] = count;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        out
    }

    /// A mask of up to `most` pixels across and down, each set with a probability drawn from
    /// `density`.
    fn random_mask(rng: &mut SeededRng, most: (usize, usize), density: (f64, f64)) -> Mask {
        let (width, height) = (1 + rng.index(most.0), 1 + rng.index(most.1));
        let density = rng.uniform(density.0, density.1);
        let set = (0..width * height).map(|_| rng.unit() < density).collect();
        Mask { width, height, set }
    }

    #[test]
    fn union_find_labels_agree_with_flood_fill_on_random_masks() {
        let mut rng = SeededRng::new(40);
        for trial in 0..200 {
            let mask = random_mask(&mut rng, (40, 30), (0.2, 0.8));
            let (labels, count) = components(&mask);
            let oracle = flood(&mask);
            let (width, height) = (mask.width, mask.height);
            assert_eq!(labels, oracle, "trial {trial}: {width}×{height}");
            assert_eq!(count, oracle.iter().copied().max().unwrap_or(0));
        }
    }

    /// The 3×3 opening by its definition: the pixels within a 3×3 window all of whose pixels are
    /// set (outside the image counts as unset). The oracle.
    fn opening(mask: &Mask) -> Vec<bool> {
        let full =
            |u: isize, v: isize| (-1..=1).all(|dv| (-1..=1).all(|du| mask.at(u + du, v + dv)));
        (0..mask.set.len())
            .map(|i| {
                let (u, v) = ((i % mask.width) as isize, (i / mask.width) as isize);
                (-1..=1).any(|dv| (-1..=1).any(|du| full(u + du, v + dv)))
            })
            .collect()
    }

    #[test]
    fn specks_are_the_components_that_the_opening_empties() {
        let mut rng = SeededRng::new(41);
        for trial in 0..300 {
            let mask = random_mask(&mut rng, (30, 20), (0.4, 0.95));
            let (parts, count) = components(&mask);
            let opened = opening(&mask);
            let mut keep = vec![false; count as usize + 1];
            for (i, &part) in parts.iter().enumerate() {
                keep[part as usize] |= opened[i];
            }
            let (kept, labels) = mask.without_specks();
            for (i, &part) in parts.iter().enumerate() {
                let expected = part != 0 && keep[part as usize];
                assert_eq!(kept.set[i], expected, "trial {trial}: pixel {i}");
                assert_eq!(labels[i], if expected { part } else { 0 });
            }
        }
    }

    #[test]
    fn a_speck_goes_and_a_square_stays_whole() {
        let (width, height) = (12, 12);
        let mut set = vec![false; width * height];
        for v in 2..8 {
            for u in 2..8 {
                set[v * width + u] = true;
            }
        }
        // A one-pixel spur on the square, which the opening would cut, stays with it.
        set[8 * width + 4] = true;
        set[10 * width + 10] = true;
        let (kept, _) = Mask {
            width,
            height,
            set: set.clone(),
        }
        .without_specks();
        set[10 * width + 10] = false;
        assert_eq!(kept.set, set);
    }

    #[test]
    fn grown_labels_claim_the_whole_blob_and_split_it_where_they_meet() {
        let (width, height) = (10, 3);
        let mask = Mask {
            width,
            height,
            set: vec![true; width * height],
        };
        let mut labels = vec![0_u32; width * height];
        labels[width + 1] = 5;
        labels[width + 8] = 9;
        let grown = grow_labels(&mask, &labels);
        assert!(grown.iter().all(|&l| l == 5 || l == 9));
        assert_eq!(grown[width], 5);
        assert_eq!(grown[width + 9], 9);
    }
}
