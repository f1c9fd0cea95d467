//! The band queue of the desktop renderer: an image's rows handed out to threads in bands, in
//! order, each band as tall as the next one should be (`band_height`). `benches/bands.rs` replays
//! it on measured band times to see how it scales to many cores.

/// The height of the next band when `left` rows remain for `workers` threads (the last band is
/// cut to the rows left): 8, the renderer's tile
/// (whose shadow lists `render_rows` builds once for all its rows), while at least two such
/// bands a worker remain; then 4, then 2. The last bands decide when the frame ends: a worker
/// that takes a tall one while the others run out of work leaves them idle, and on many cores an
/// image has too few 8-row bands to go round. Heights only fall, each a power of two, so every
/// band starts on a multiple of its height. A lone worker keeps 8: nobody waits for it.
pub fn band_height(left: usize, workers: usize) -> usize {
    let mut rows = 8;
    while workers > 1 && rows > 2 && left < 2 * rows * workers {
        rows /= 2;
    }
    rows
}

/// The rows of an image not yet handed out, `width` pixels a row, from row `next` on.
#[derive(Debug)]
pub struct Bands<'a, T> {
    rest: &'a mut [T],
    width: usize,
    next: usize,
    workers: usize,
}

impl<'a, T> Bands<'a, T> {
    /// The bands of `image`, `width` pixels a row, for `workers` threads.
    pub fn new(image: &'a mut [T], width: usize, workers: usize) -> Self {
        Bands {
            rest: image,
            width: width.max(1),
            next: 0,
            workers: workers.max(1),
        }
    }
}

impl<'a, T> Iterator for Bands<'a, T> {
    /// The band's first row, and its pixels.
    type Item = (usize, &'a mut [T]);

    fn next(&mut self) -> Option<Self::Item> {
        let left = self.rest.len() / self.width;
        if left == 0 {
            return None;
        }
        let rows = band_height(left, self.workers).min(left);
        let rest = core::mem::take(&mut self.rest);
        let (band, rest) = rest.split_at_mut(rows * self.width);
        self.rest = rest;
        let row = self.next;
        self.next += rows;
        Some((row, band))
    }
}

#[cfg(test)]
mod tests {
    // Paths, not a `use`: `benches/bands.rs` compiles this file without running its tests.
    #[test]
    fn bands_cover_the_image_in_order_on_multiples_of_their_height() {
        for (h, workers) in [(480, 1), (480, 2), (480, 64), (1080, 16), (7, 2), (1, 1)] {
            let mut image = vec![0u8; 3 * h];
            let mut row = 0;
            let mut last = 8;
            for (start, band) in super::Bands::new(&mut image, 3, workers) {
                let rows = band.len() / 3;
                assert_eq!(start, row);
                assert!(rows >= 1 && rows <= last, "heights only fall");
                assert!(start % rows == 0 || start + rows == h, "{start} {rows}");
                band.fill(1);
                row += rows;
                last = rows;
            }
            assert_eq!(row, h);
            assert!(image.iter().all(|&p| p == 1));
        }
        assert_eq!(super::band_height(480, 1), 8);
        assert_eq!(super::band_height(20, 1), 8);
        assert_eq!(super::band_height(480, 64), 2);
        assert_eq!(super::band_height(20, 2), 4);
        assert_eq!(super::band_height(12, 2), 2);
    }
}
