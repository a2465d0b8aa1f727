//! The soil's memory (issue 30): a sparse grid of square cells over each soil surface, in
//! tiles of [`TILE_CELLS`]^2 cells created where the vehicle loads the soil. A cell keeps the
//! largest sinkage it was pressed to (the rut), the shear displacement accumulated while it is
//! under a track, the step it was last loaded and the time it was first loaded (the replay).
//!
//! Bounded memory: at most `max_tiles` tiles per soil; creating one more forgets the tile
//! loaded least recently (ties: the lowest tile key), so a long drive keeps the ruts near the
//! vehicle and forgets the oldest. One tile is `TILE_CELLS^2 x 16` bytes (64 KiB).
//!
//! Cells are indexed in world coordinates, `floor(x / cell)`, computed as the floating origin's
//! whole cells plus the cells of the Rapier (f32) coordinate, so a shift of the origin by whole
//! metres leaves every index unchanged (a cell divides a metre).

use crate::terrain::soil::TILE_CELLS;
use rustc_hash::FxHashMap;

/// One cell of soil.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cell {
    /// Largest sinkage the cell was pressed to, m (below the undisturbed surface).
    pub z_max: f32,
    /// Shear displacement accumulated since the cell came under a track, m.
    pub j: f32,
    /// Step number + 1 when the cell was last loaded (0: never).
    pub last: u32,
    /// Simulated time the cell was first loaded, s.
    pub t_first: f32,
}

/// A tile: [`TILE_CELLS`]^2 cells, row-major in y then x.
struct Tile {
    key: TileKey,
    cells: Box<[Cell]>,
    /// Step number of the last load.
    last: u32,
}

/// Key of a tile: soil index and tile indices.
type TileKey = (u32, i64, i64);

/// The grid of every soil of a world.
pub struct RutGrid {
    /// Tiles, in no particular order; `index` finds them by key.
    tiles: Vec<Tile>,
    index: FxHashMap<TileKey, usize>,
    /// Tiles kept per soil at most, by soil index.
    max_tiles: Vec<usize>,
    /// Tiles held per soil.
    held: Vec<usize>,
    /// Tiles forgotten so far.
    evicted: u64,
}

/// What the grid holds, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct RutGridStats {
    /// Tiles held.
    pub tiles: usize,
    /// Bytes of cell data held.
    pub bytes: usize,
    /// Tiles forgotten to stay within the bound.
    pub evicted: u64,
    /// The bound, bytes (sum over the soils of `max_tiles` tiles).
    pub max_bytes: usize,
}

const TILE: i64 = TILE_CELLS as i64;

/// Reads cells of one soil, remembering the last tile it found (patches are small, so most
/// cells of a patch share a tile).
pub struct Reader<'a> {
    grid: &'a RutGrid,
    soil: u32,
    last: Option<(TileKey, Option<usize>)>,
}

impl Reader<'_> {
    /// The cell at world cell indices (ix, iy), if its tile exists.
    pub fn cell(&mut self, ix: i64, iy: i64) -> Option<&Cell> {
        let (k, i) = split(self.soil, ix, iy);
        let t = match self.last {
            Some((lk, t)) if lk == k => t,
            _ => {
                let t = self.grid.index.get(&k).copied();
                self.last = Some((k, t));
                t
            }
        };
        t.map(|t| &self.grid.tiles[t].cells[i])
    }
}

/// Writes cells of one soil at one step, remembering the last tile.
pub struct Writer<'a> {
    grid: &'a mut RutGrid,
    soil: u32,
    step: u32,
    last: Option<(TileKey, usize)>,
}

impl Writer<'_> {
    /// The cell at (ix, iy) for writing (its tile created, and the least recently loaded tile
    /// of the soil forgotten if the soil already holds its `max_tiles`).
    pub fn cell(&mut self, ix: i64, iy: i64) -> &mut Cell {
        let (k, i) = split(self.soil, ix, iy);
        let t = match self.last {
            Some((lk, t)) if lk == k => t,
            _ => {
                let t = self.grid.tile_for(k, self.step);
                self.last = Some((k, t));
                t
            }
        };
        let tile = &mut self.grid.tiles[t];
        tile.last = self.step;
        &mut tile.cells[i]
    }
}

impl RutGrid {
    /// An empty grid for soils keeping at most `max_tiles[i]` tiles each.
    pub fn new(max_tiles: Vec<usize>) -> Self {
        RutGrid {
            tiles: Vec::new(),
            index: FxHashMap::default(),
            held: vec![0; max_tiles.len()],
            max_tiles,
            evicted: 0,
        }
    }

    /// A reader of soil `soil`'s cells.
    pub fn reader(&self, soil: usize) -> Reader<'_> {
        Reader {
            grid: self,
            soil: soil as u32,
            last: None,
        }
    }

    /// A writer of soil `soil`'s cells at step `step`.
    pub fn writer(&mut self, soil: usize, step: u32) -> Writer<'_> {
        Writer {
            grid: self,
            soil: soil as u32,
            step,
            last: None,
        }
    }

    /// The index of tile `k`, created (after making room) if needed.
    fn tile_for(&mut self, k: TileKey, step: u32) -> usize {
        if let Some(&t) = self.index.get(&k) {
            return t;
        }
        self.evict_for(k.0 as usize);
        self.tiles.push(Tile {
            key: k,
            cells: vec![Cell::default(); TILE_CELLS * TILE_CELLS].into_boxed_slice(),
            last: step,
        });
        let t = self.tiles.len() - 1;
        self.index.insert(k, t);
        if let Some(h) = self.held.get_mut(k.0 as usize) {
            *h += 1;
        }
        t
    }

    /// Makes room for one more tile of `soil`: forgets its tile loaded least recently (ties:
    /// the lowest key).
    fn evict_for(&mut self, soil: usize) {
        let cap = self.max_tiles.get(soil).copied().unwrap_or(usize::MAX);
        if self.held.get(soil).copied().unwrap_or(0) < cap {
            return;
        }
        let oldest = self
            .tiles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.key.0 == soil as u32)
            .min_by_key(|(_, t)| (t.last, t.key))
            .map(|(i, _)| i);
        if let Some(i) = oldest {
            let gone = self.tiles.swap_remove(i);
            self.index.remove(&gone.key);
            if let Some(moved) = self.tiles.get(i) {
                self.index.insert(moved.key, i);
            }
            self.held[soil] -= 1;
            self.evicted += 1;
        }
    }

    /// What the grid holds.
    pub fn stats(&self) -> RutGridStats {
        let per = TILE_CELLS * TILE_CELLS * std::mem::size_of::<Cell>();
        RutGridStats {
            tiles: self.tiles.len(),
            bytes: self.tiles.len() * per,
            evicted: self.evicted,
            max_bytes: self.max_tiles.iter().sum::<usize>() * per,
        }
    }

    /// Every loaded cell: (soil, ix, iy, cell), sorted by soil, then tile, then y, then x.
    pub fn loaded_cells(&self) -> Vec<(usize, i64, i64, Cell)> {
        let mut order: Vec<&Tile> = self.tiles.iter().collect();
        order.sort_by_key(|t| t.key);
        let mut out = Vec::new();
        for t in order {
            let k = t.key;
            for (i, c) in t.cells.iter().enumerate() {
                if c.last > 0 {
                    let (x, y) = ((i % TILE_CELLS) as i64, (i / TILE_CELLS) as i64);
                    out.push((k.0 as usize, k.1 * TILE + x, k.2 * TILE + y, *c));
                }
            }
        }
        out
    }
}

/// The tile key and the index in the tile of world cell (ix, iy).
fn split(soil: u32, ix: i64, iy: i64) -> (TileKey, usize) {
    let (tx, ty) = (ix.div_euclid(TILE), iy.div_euclid(TILE));
    let (x, y) = (ix.rem_euclid(TILE), iy.rem_euclid(TILE));
    ((soil, tx, ty), (y * TILE + x) as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_indices_and_eviction_stay_bounded() {
        let mut g = RutGrid::new(vec![2]);
        g.writer(0, 1).cell(-1, -1).z_max = 0.01;
        assert_eq!(g.reader(0).cell(-1, -1).unwrap().z_max, 0.01);
        assert!(g.reader(0).cell(0, 0).is_none());
        g.writer(0, 2).cell(100, 0);
        // A third tile forgets the one loaded least recently (step 1).
        g.writer(0, 3).cell(1000, 0).z_max = 0.02;
        assert!(g.reader(0).cell(-1, -1).is_none());
        assert_eq!(g.reader(0).cell(1000, 0).unwrap().z_max, 0.02);
        let s = g.stats();
        assert_eq!((s.tiles, s.evicted), (2, 1));
        assert_eq!(s.bytes, 2 * 64 * 64 * 16);
    }
}
