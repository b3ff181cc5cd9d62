//! CPU image compositing around the GPU passes: the figure sequence every front end
//! calls (`figure`: the frame, then its labels, caption and colour bar), the magnitude
//! colour bar (`colorbar`), text, edge labels and lightbox captions (`labels`), and the
//! grid of `--views`/`--lightbox` panels (`montage`), which draws each panel by the
//! figure sequence and lays the pixels out. Supersampling's box filter is
//! `render::antialias`.
pub mod colorbar;
pub mod figure;
pub mod labels;
pub mod montage;
