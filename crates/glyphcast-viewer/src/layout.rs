//! Where things go in the window: the colour bar's strip (`--colorbar`) on the right, as
//! `render --colorbar` appends it, and the panels (one, or the cells of a montage's grid,
//! as `render --views/--lightbox` lays them out) in the rest. The screenshot composes
//! the same layout, so window and screenshot put every panel and the strip at the same
//! pixels.
use ash::vk;
use glyphcast::render::compose::montage::Grid;

/// The layout of a window of a given size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowLayout {
    /// The whole window.
    pub width: u32,
    pub height: u32,
    /// The panels' cells, from the window's corner: panel k at `grid.cell_origin(k)`.
    pub grid: Grid,
    /// The number of panels.
    pub panels: usize,
    /// The colour bar's strip: its left edge and width (the window's height).
    pub strip: Option<(u32, u32)>,
}

impl WindowLayout {
    /// The layout of a `width` x `height` window showing `panels` panels, `columns` to a
    /// row, and a colour bar strip `strip_width` pixels wide, if any. The strip is
    /// reserved on the right (the panels share what is left) unless the window is too
    /// narrow to leave them a column, when it is left out. Cells are the largest that
    /// fit; pixels the grid leaves over are background.
    pub fn new(
        width: u32,
        height: u32,
        panels: usize,
        columns: usize,
        strip_width: Option<u32>,
    ) -> WindowLayout {
        let strip = strip_width
            .filter(|&w| w > 0 && w < width)
            .map(|w| (width - w, w));
        let area = strip.map_or(width, |(left, _)| left);
        let shape = Grid::new((1, 1), columns, panels);
        let cell = (area / shape.columns as u32, height / shape.rows as u32);
        WindowLayout {
            width,
            height,
            grid: Grid { cell, ..shape },
            panels: panels.max(1),
            strip,
        }
    }

    /// The size of the grid that gives each of `panels` panels (`columns` to a row) a
    /// cell of `cell`: the window's size without the strip.
    pub fn grid_size(cell: (u32, u32), panels: usize, columns: usize) -> (u32, u32) {
        let grid = Grid::new(cell, columns, panels);
        (
            cell.0.saturating_mul(grid.columns as u32),
            cell.1.saturating_mul(grid.rows as u32),
        )
    }

    /// Panel k's cell in the window, None where it has no area.
    pub fn cell(&self, k: usize) -> Option<vk::Rect2D> {
        let (cw, ch) = self.grid.cell;
        if cw == 0 || ch == 0 || k >= self.panels {
            return None;
        }
        let (x, y) = self.grid.cell_origin(k);
        Some(vk::Rect2D {
            offset: vk::Offset2D {
                x: x as i32,
                y: y as i32,
            },
            extent: vk::Extent2D {
                width: cw,
                height: ch,
            },
        })
    }

    /// The strip's rectangle, if the window shows one.
    pub fn strip_rect(&self) -> Option<vk::Rect2D> {
        self.strip.map(|(left, width)| vk::Rect2D {
            offset: vk::Offset2D {
                x: left as i32,
                y: 0,
            },
            extent: vk::Extent2D {
                width,
                height: self.height,
            },
        })
    }

    /// The width of the area left of the strip (the whole window without one).
    pub fn panel_area_width(&self) -> u32 {
        self.strip.map_or(self.width, |(left, _)| left)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_strip_is_reserved_on_the_right() {
        let layout = WindowLayout::new(260, 200, 1, 1, Some(60));
        assert_eq!(layout.strip, Some((200, 60)));
        assert_eq!(layout.grid.cell, (200, 200));
        let rect = layout.strip_rect().unwrap();
        assert_eq!(
            (rect.offset.x, rect.extent.width, rect.extent.height),
            (200, 60, 200)
        );
        // Too narrow for the strip and a panel: no strip.
        let narrow = WindowLayout::new(50, 200, 1, 1, Some(60));
        assert_eq!((narrow.strip, narrow.grid.cell), (None, (50, 200)));
    }

    #[test]
    fn a_montage_fills_a_grid_in_reading_order() {
        let (w, h) = WindowLayout::grid_size((72, 56), 4, 2);
        assert_eq!((w, h), (2 * 72, 112));
        let layout = WindowLayout::new(w + 28, h, 4, 2, Some(28));
        assert_eq!(layout.grid.cell, (72, 56));
        let third = layout.cell(2).unwrap();
        assert_eq!((third.offset.x, third.offset.y), (0, 56));
        assert_eq!(layout.cell(4), None);
        // Leftover pixels are background: 150 / 2 columns = 75, 101 / 2 rows = 50.
        let uneven = WindowLayout::new(150, 101, 3, 2, None);
        assert_eq!(uneven.grid.cell, (75, 50));
        assert_eq!(uneven.cell(3), None);
    }
}
