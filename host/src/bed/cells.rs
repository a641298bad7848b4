//! The cell grid: doubly linked lists of the disks in each cell.
//!
//! Cells are at least one diameter wide and high, so a disk can only touch disks of its own cell
//! and the eight around it. The grid spans x ∈ [0, L) (periodic) and y from the piston's lowest
//! position −A/2 to the lid.

/// "No disk" in the linked lists.
pub const NONE: u32 = u32::MAX;

/// A grid of `nx × ny` cells of `wx × wy` (m), its bottom at height `y0` (m).
#[derive(Debug, Clone)]
pub struct Cells {
    /// Cells across (≥ 3, so the eight neighbours are distinct).
    pub nx: usize,
    /// Cells up.
    pub ny: usize,
    /// Cell width (m).
    pub wx: f64,
    /// Cell height (m).
    pub wy: f64,
    /// Bottom of the grid (m).
    pub y0: f64,
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// The cell of each disk.
    pub cell: Vec<u32>,
    /// The column and row of each disk's cell (so that no prediction divides).
    pub col_row: Vec<(u32, u32)>,
}

impl Cells {
    /// A grid over width `width` and heights [y0, y1] with cells no smaller than `min_size`,
    /// for `n` disks.
    pub fn new(width: f64, y0: f64, y1: f64, min_size: f64, n: usize) -> Cells {
        let nx = ((width / min_size).floor() as usize).max(1);
        let ny = (((y1 - y0) / min_size).floor() as usize).max(1);
        Cells {
            nx,
            ny,
            wx: width / nx as f64,
            wy: (y1 - y0) / ny as f64,
            y0,
            head: vec![NONE; nx * ny + 1],
            next: vec![NONE; n],
            prev: vec![NONE; n],
            cell: vec![NONE; n],
            col_row: vec![(0, 0); n],
        }
    }

    /// The cell containing (x, y), clamped to the grid.
    pub fn locate(&self, x: f64, y: f64) -> u32 {
        let cx = ((x / self.wx).floor().max(0.0) as usize).min(self.nx - 1);
        let cy = (((y - self.y0) / self.wy).floor().max(0.0) as usize).min(self.ny - 1);
        (cy * self.nx + cx) as u32
    }

    /// A cell that is never filled, after the grid's: what a prediction visits for the rows
    /// beyond the grid, so that it always visits the same number of cells.
    #[inline]
    pub fn outside(&self) -> usize {
        self.nx * self.ny
    }

    /// The first disk of cell `c`.
    #[inline]
    pub fn head(&self, c: usize) -> u32 {
        self.head[c]
    }

    /// The disk after `i` in its cell.
    #[inline]
    pub fn next(&self, i: usize) -> u32 {
        self.next[i]
    }

    /// Puts disk `i` into cell `c`.
    #[inline]
    pub fn insert(&mut self, i: usize, c: u32) {
        self.link(i, c, (c % self.nx as u32, c / self.nx as u32));
    }

    /// Moves disk `i` to the cell of column `cx` and row `cy`.
    #[inline]
    pub fn moveto_xy(&mut self, i: usize, cx: usize, cy: usize) {
        self.remove(i);
        self.link(i, (cy * self.nx + cx) as u32, (cx as u32, cy as u32));
    }

    /// Links disk `i` at the head of cell `c` (of column and row `col_row`).
    #[inline(always)]
    fn link(&mut self, i: usize, c: u32, col_row: (u32, u32)) {
        let h = self.head[c as usize];
        self.next[i] = h;
        self.prev[i] = NONE;
        if h != NONE {
            self.prev[h as usize] = i as u32;
        }
        self.head[c as usize] = i as u32;
        self.cell[i] = c;
        self.col_row[i] = col_row;
    }

    /// Takes disk `i` out of its cell.
    #[inline(always)]
    pub fn remove(&mut self, i: usize) {
        let (p, n) = (self.prev[i], self.next[i]);
        if p != NONE {
            self.next[p as usize] = n;
        } else {
            self.head[self.cell[i] as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
        self.cell[i] = NONE;
    }

    /// Moves disk `i` to cell `c`.
    #[inline]
    pub fn moveto(&mut self, i: usize, c: u32) {
        self.remove(i);
        self.insert(i, c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_remove_and_locate() {
        let mut c = Cells::new(0.2, -0.0125, 0.03, 0.002, 4);
        assert_eq!(c.nx, 100);
        assert!(c.wy >= 0.002);
        let a = c.locate(0.0011, -0.0125 + 1.5 * c.wy);
        assert_eq!(a as usize, c.nx);
        for i in 0..3 {
            c.insert(i, a);
        }
        c.moveto(1, 0);
        let mut in_a = vec![];
        let mut k = c.head(a as usize);
        while k != NONE {
            in_a.push(k);
            k = c.next(k as usize);
        }
        assert_eq!(in_a, vec![2, 0]);
        assert_eq!(c.head(0), 1);
        assert_eq!(c.locate(-1.0, -1.0), 0);
        // the cell beyond the grid is never located, so never filled
        assert_eq!(c.locate(1.0, 1.0) as usize, c.outside() - 1);
        assert_eq!(c.head(c.outside()), NONE);
    }
}
