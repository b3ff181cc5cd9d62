//! CPU image compositing around the GPU passes: the magnitude colour bar (`colorbar`),
//! text, edge labels and lightbox captions (`labels`), and the grid of
//! `--views`/`--lightbox` panels (`montage`), which draws each panel with the headless
//! renderer and lays the pixels out. Supersampling's box filter is `render::antialias`.
pub mod colorbar;
pub mod labels;
pub mod montage;
