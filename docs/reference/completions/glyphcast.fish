# Print an optspec for argparse to handle cmd's options that are independent of any subcommand.
function __fish_glyphcast_global_optspecs
    string join \n h/help V/version
end

function __fish_glyphcast_needs_command
    # Figure out if the current invocation already has a command.
    set -l cmd (commandline -opc)
    set -e cmd[1]
    argparse -s (__fish_glyphcast_global_optspecs) -- $cmd 2>/dev/null
    or return
    if set -q argv[1]
        # Also print the command, so this can be used to figure out what it is.
        echo $argv[1]
        return 1
    end
    return 0
end

function __fish_glyphcast_using_subcommand
    set -l cmd (__fish_glyphcast_needs_command)
    test -z "$cmd"
    and return 1
    contains -- $cmd[1] $argv
end

complete -c glyphcast -n "__fish_glyphcast_needs_command" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -s V -l version -d 'Print version'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "render" -d 'Render a scene file (docs/scene-format.md) or a volume to a PNG, and optionally a depth map'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "view" -d 'Show a scene file or a volume in a window: orbit, pan and zoom with the mouse, keys for the method, step, refinement, colour, negative lobes and the slice'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "demo" -d 'Render the built-in demo scene (a field of crossing-fibre glyphs)'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "accuracy" -d 'Measure every method against the float64 reference on the accuracy suite'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "bench" -d 'GPU timings of the glyph pass: one scene or workload, or a sweep'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "fit" -d 'Fit tensor, SH or fibre-ODF (CSD, CSA, Q-ball) coefficients to a DWI series (writes a 4D NIfTI or MRtrix image)'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "peaks" -d 'Find up to N maxima per voxel of an ODF image (MRtrix sh2peaks\' layout)'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "qc" -d 'Write one subject\'s quality-control figure set of fibre ODFs into a folder: ODF mosaic, zoomed regions, index.html and the qc.json sidecar'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "stiffness" -d 'Write a scene of stiffness glyphs from Voigt matrices (text, CSV or JSON), and the elastic extremes and averages (--summary)'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "reference" -d 'Write the command-line reference into a folder: a Markdown page per command, man pages and shell completions (tools/gen-docs.sh writes docs/reference/)'
complete -c glyphcast -n "__fish_glyphcast_needs_command" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l sh -d '4D image of SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even band L <= 12: NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, .mih); see --frame' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l basis -d 'SH basis of --sh: tournier07 or descoteaux07 (with --legacy for the legacy variant), or mrtrix (= tournier07, dwi2fod\'s output), dipy (= descoteaux07 legacy, DIPY\'s default) or dipy-new (= descoteaux07). Default: the basis the file records (glyphcast fit writes it), tournier07 for MRtrix images without a record' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l frame -d 'Axes of the coefficients: voxel (the image\'s voxel axes, as DIPY writes them; glyphs are turned by the affine\'s rotation) or world (scanner axes, as MRtrix stores them and glyphcast fit writes them). Default: voxel for NIfTI, world for MRtrix images (unless the header says glyphcast_frame: voxel)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l lmax -d 'Draw SH bands up to L only' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l tensor -d '4D NIfTI or MRtrix image of Cartesian tensor coefficients: order 2 in the order of --tensor-order, higher orders in the scene format\'s order' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l tensor-order -d 'Stored order of an order-2 --tensor\'s six entries: glyphcast (xx, xy, xz, yy, yz, zz; also FSL\'s dtifit), fsl, mrtrix (xx, yy, zz, xy, xz, yz; dwi2tensor) or dipy (xx, xy, yy, xz, yz, zz; lower_triangular). Default: what the file records (glyphcast fit writes it), mrtrix for .mif, else glyphcast, refused where the values show another order' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l order -d 'Tensor order of --tensor (1 to 12)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l slice -d 'Slice to draw: axial, coronal or sagittal, the world\'s planes (across scanner z, y or x; the voxel plane closest to it: constant k, j or i for an axial acquisition), optionally :INDEX along that voxel axis (default: the middle axial slice)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l slices -d 'Three orthogonal slices at once instead of --slice: voxel indices I,J,K of the sagittal, coronal and axial slice, or mid (the middle of each); seen in perspective from superior-left, anterior (radiological) or posterior (neurological)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l voxels -d 'Voxel index ranges i0:i1,j0:j1,k0:k1 (end exclusive, ends optional), intersected with the slice' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l mask -d '3D NIfTI or MRtrix mask of the volume\'s shape: glyphs only where it is nonzero' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l scale -d 'World radius of the largest glyph (default: 0.45 times the smallest voxel size)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l norm -d 'Glyph sizes: robust (one factor for all: the largest glyph that is no outlier at --scale, an outlier being more than 1.5 times the 99th percentile of the glyph sizes, drawn at --scale itself; the default), global (one factor for all, the largest at --scale), per-glyph (all the same size) or none (amplitude times --scale)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l min-amplitude -d 'Leave out glyphs whose largest radius is below A (data units)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l orientation -d 'radiological (the subject\'s right on the image\'s left in axial and coronal views, as mrview shows them; the default) or neurological (right on the right). Sagittal views have anterior on the left in both' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l underlay -d 'Anatomical underlay drawn as a plane behind each slice\'s glyphs (of every panel of --views/--lightbox), in the glyphs\' depth buffer: a 3D NIfTI or MRtrix image (FA, T1) or an RGB one [x, y, z, 3] (colour-FA), sampled trilinearly through its own affine (the grids may differ)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l underlay-range -d 'The underlay\'s window: LOW is drawn black, HIGH white (each RGB channel alike). Default: the 2nd to 98th percentile of its finite values' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l underlay-plane -d 'Where the underlay\'s plane lies: back (behind the glyphs: as far behind the slice, seen from the camera, as the largest glyph reaches; the default) or centre (through the voxel centres, hiding each glyph\'s far half)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l glyph -d 'Glyph surface: polynomial (the glyph of the tensor or SH series, the default) or ellipsoid (order-2 tensors: the DTI ellipsoid { D^(1/2) u }, semi-axes sqrt(eigenvalues), eigenvalues below 1e-6 of the largest raised to that floor). For a scene file it sets every glyph set\'s `shape`' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l views -d 'One image (view: one window) with a panel per view, left to right: a comma-separated list of axial, coronal and sagittal (any subset, any order; each optionally :INDEX as for --slice), each panel --width x --height' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l lightbox -d 'N evenly spaced slices along the --slice plane (default axial) in a grid of ceil(sqrt(N)) columns, each panel --width x --height' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks -d 'Fibre peaks drawn in the voxels of the slices, as capsules through the voxel centres in the glyphs\' depth buffer: a 4D image of 3 values per peak, direction times amplitude, NaN where absent (glyphcast peaks, MRtrix sh2peaks), or with --peak-values DIPY\'s unit peak_dirs (4D [x, y, z, 3N] or 5D [x, y, z, N, 3]). On the glyphs\' grid; alone (without --sh/--tensor) the peaks\' grid frames the view. Directions are in the file\'s own frame (voxel axes for NIfTI, scanner axes for MRtrix images unless the header says otherwise); --peaks-frame names another' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks-frame -d 'Axes of the --peaks directions: voxel or world (scanner). Default: voxel for NIfTI, world for MRtrix images. MRtrix\'s sh2peaks writes scanner axes into a NIfTI too: give world for such a file' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peak-values -d 'DIPY\'s peak_values [x, y, z, N]: the amplitudes of --peaks, whose directions are then unit vectors (the DIPY layout)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks-color -d 'Peak colour: direction (RGB = |x|, |y|, |z| of the world direction, the default), a name (white, black, grey, red, green, blue, yellow, cyan, magenta), #rrggbb or r,g,b (0-255)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks-norm -d 'Peak lengths: global (proportional to the amplitude, the longest drawn gets --peaks-scale; the default), unit (all --peaks-scale) or none (amplitude times --peaks-scale)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks-scale -d 'World half length of the longest peak (default: 0.5 times the smallest voxel size, so that it spans its voxel)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l peaks-width -d 'Peak diameter in pixels (default 2; at the target in a perspective view)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l save-scene -d 'Also write the scene that is rendered as a scene file (with the image, all or nothing)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -s o -l output -d 'Output image (PNG)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l depth-out -d 'Also write the ray distance per pixel as a float32 .npy (NaN for misses)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l dpi -d 'The print resolution recorded in the PNG (its pHYs chunk), in pixels per inch: a layout program then places the image at width / DPI inches' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l width -d 'Image width in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l height -d 'Image height in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l scale-factor -d 'Multiply the image\'s width and height by F, keeping its framing: the same figure with more pixels (labels, captions and the colour bar grow with it)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l method -d ' How glyphs are drawn: fixed (ray casting at a fixed step), interval or affine (robust ray casting by range arithmetic), exact (first real root of the ray polynomial; offset 0 only), impostor (bounding spheres), mesh:LEVEL (icosphere) or latlong:N (latitude bands) tessellations. Accepts fixed, interval, affine, exact, impostor, mesh:0 to mesh:7, latlong:N; default exact, or affine with an offset.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l path -d ' Which ray caster runs the method: fragment (proxy boxes) or compute (a compute shader per pixel over screen tiles; exact only). Accepts fragment, compute; default fragment.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l precision -d ' The robust methods\' segment length limit, in pixels at the segment\'s depth. Accepts 0.01 to 64; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l step -d ' The fixed march\'s step, in units of each glyph\'s bounding radius. Accepts 0.001 to 2; default 0.02.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l refine -d ' The refinement of the first sign change along the ray. Accepts bisect:K, secant:K (K = 0 to 16), interp, none; default secant:4.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l color -d ' Glyph colour: direction, magnitude, uniform or sign (positive lobes red, negative ones blue; ray-casting methods only). Accepts direction, magnitude, uniform, sign; default direction.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l magnitude-range -d ' The magnitude colour map\'s range, LOW:HIGH in world units. Accepts two numbers, low below high; default 0 to the largest glyph radius drawn.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l negative -d ' Negative lobes: abs (drawn as |f|) or hide; replaces every glyph set\'s mode. Accepts abs, hide; default the scene\'s (abs for volumes).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l background -d ' Background: none (transparent PNG), a name, #rrggbb or r,g,b (sRGB, 0 to 255, as written in the PNG). Accepts none, dark, black, white, grey, #rrggbb, r,g,b; default dark.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l offset -d ' Isotropic offset added to every glyph, as a fraction of its bounding radius. Accepts a number >= 0; default 0.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l light -d ' Direction towards the light, X,Y,Z in view coordinates (x to the image\'s right, y up, z towards the viewer); the light moves with the camera. Accepts three numbers, not all 0; default 0.35,0.5,1 (above right, in front).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l ambient -d ' Ambient share of the base colour. Accepts 0 to 1; default 0.18.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l specular -d ' Strength of the white specular highlight (0: matte). Accepts 0 to 1; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l shininess -d ' Blinn-Phong exponent of the highlight. Accepts 1 to 1024; default 48.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l samples -d ' Samples per pixel: supersampling draws at 2 or 4 times the width and height, then averages; the depth map stays one ray per pixel centre. Accepts 1, 4, 16; default 1.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l colorbar-label -d 'The colour bar\'s label (default: "radius (data units)" or "radius (world units)")' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l device -d 'Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l force-basis -d 'Use --basis even where the file records another basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l legacy -d 'The legacy variant of --basis (DIPY\'s legacy=True; MRtrix 0.2 for tournier07)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l nonsymmetric -d '--tensor holds all 3^N entries, row-major, instead of the unique ones'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l perspective -d 'Perspective camera instead of orthographic'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l labels -d 'Write the anatomical directions (L/R, A/P, S/I) at the image\'s edges (of every panel of a montage)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l colorbar -d 'With --color magnitude: append a colour bar of the magnitude range on the right, in a strip of its own (the PNG and the depth map grow by its width; the depth map is NaN there). Values are glyph radii in data units (|f|, or an ellipsoid\'s sqrt(eigenvalue)) when every glyph has the same scale, else in world units'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -l validation -d 'Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand render" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l sh -d '4D image of SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even band L <= 12: NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, .mih); see --frame' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l basis -d 'SH basis of --sh: tournier07 or descoteaux07 (with --legacy for the legacy variant), or mrtrix (= tournier07, dwi2fod\'s output), dipy (= descoteaux07 legacy, DIPY\'s default) or dipy-new (= descoteaux07). Default: the basis the file records (glyphcast fit writes it), tournier07 for MRtrix images without a record' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l frame -d 'Axes of the coefficients: voxel (the image\'s voxel axes, as DIPY writes them; glyphs are turned by the affine\'s rotation) or world (scanner axes, as MRtrix stores them and glyphcast fit writes them). Default: voxel for NIfTI, world for MRtrix images (unless the header says glyphcast_frame: voxel)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l lmax -d 'Draw SH bands up to L only' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l tensor -d '4D NIfTI or MRtrix image of Cartesian tensor coefficients: order 2 in the order of --tensor-order, higher orders in the scene format\'s order' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l tensor-order -d 'Stored order of an order-2 --tensor\'s six entries: glyphcast (xx, xy, xz, yy, yz, zz; also FSL\'s dtifit), fsl, mrtrix (xx, yy, zz, xy, xz, yz; dwi2tensor) or dipy (xx, xy, yy, xz, yz, zz; lower_triangular). Default: what the file records (glyphcast fit writes it), mrtrix for .mif, else glyphcast, refused where the values show another order' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l order -d 'Tensor order of --tensor (1 to 12)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l slice -d 'Slice to draw: axial, coronal or sagittal, the world\'s planes (across scanner z, y or x; the voxel plane closest to it: constant k, j or i for an axial acquisition), optionally :INDEX along that voxel axis (default: the middle axial slice)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l slices -d 'Three orthogonal slices at once instead of --slice: voxel indices I,J,K of the sagittal, coronal and axial slice, or mid (the middle of each); seen in perspective from superior-left, anterior (radiological) or posterior (neurological)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l voxels -d 'Voxel index ranges i0:i1,j0:j1,k0:k1 (end exclusive, ends optional), intersected with the slice' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l mask -d '3D NIfTI or MRtrix mask of the volume\'s shape: glyphs only where it is nonzero' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l scale -d 'World radius of the largest glyph (default: 0.45 times the smallest voxel size)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l norm -d 'Glyph sizes: robust (one factor for all: the largest glyph that is no outlier at --scale, an outlier being more than 1.5 times the 99th percentile of the glyph sizes, drawn at --scale itself; the default), global (one factor for all, the largest at --scale), per-glyph (all the same size) or none (amplitude times --scale)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l min-amplitude -d 'Leave out glyphs whose largest radius is below A (data units)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l orientation -d 'radiological (the subject\'s right on the image\'s left in axial and coronal views, as mrview shows them; the default) or neurological (right on the right). Sagittal views have anterior on the left in both' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l underlay -d 'Anatomical underlay drawn as a plane behind each slice\'s glyphs (of every panel of --views/--lightbox), in the glyphs\' depth buffer: a 3D NIfTI or MRtrix image (FA, T1) or an RGB one [x, y, z, 3] (colour-FA), sampled trilinearly through its own affine (the grids may differ)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l underlay-range -d 'The underlay\'s window: LOW is drawn black, HIGH white (each RGB channel alike). Default: the 2nd to 98th percentile of its finite values' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l underlay-plane -d 'Where the underlay\'s plane lies: back (behind the glyphs: as far behind the slice, seen from the camera, as the largest glyph reaches; the default) or centre (through the voxel centres, hiding each glyph\'s far half)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l glyph -d 'Glyph surface: polynomial (the glyph of the tensor or SH series, the default) or ellipsoid (order-2 tensors: the DTI ellipsoid { D^(1/2) u }, semi-axes sqrt(eigenvalues), eigenvalues below 1e-6 of the largest raised to that floor). For a scene file it sets every glyph set\'s `shape`' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l views -d 'One image (view: one window) with a panel per view, left to right: a comma-separated list of axial, coronal and sagittal (any subset, any order; each optionally :INDEX as for --slice), each panel --width x --height' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l lightbox -d 'N evenly spaced slices along the --slice plane (default axial) in a grid of ceil(sqrt(N)) columns, each panel --width x --height' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks -d 'Fibre peaks drawn in the voxels of the slices, as capsules through the voxel centres in the glyphs\' depth buffer: a 4D image of 3 values per peak, direction times amplitude, NaN where absent (glyphcast peaks, MRtrix sh2peaks), or with --peak-values DIPY\'s unit peak_dirs (4D [x, y, z, 3N] or 5D [x, y, z, N, 3]). On the glyphs\' grid; alone (without --sh/--tensor) the peaks\' grid frames the view. Directions are in the file\'s own frame (voxel axes for NIfTI, scanner axes for MRtrix images unless the header says otherwise); --peaks-frame names another' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks-frame -d 'Axes of the --peaks directions: voxel or world (scanner). Default: voxel for NIfTI, world for MRtrix images. MRtrix\'s sh2peaks writes scanner axes into a NIfTI too: give world for such a file' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peak-values -d 'DIPY\'s peak_values [x, y, z, N]: the amplitudes of --peaks, whose directions are then unit vectors (the DIPY layout)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks-color -d 'Peak colour: direction (RGB = |x|, |y|, |z| of the world direction, the default), a name (white, black, grey, red, green, blue, yellow, cyan, magenta), #rrggbb or r,g,b (0-255)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks-norm -d 'Peak lengths: global (proportional to the amplitude, the longest drawn gets --peaks-scale; the default), unit (all --peaks-scale) or none (amplitude times --peaks-scale)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks-scale -d 'World half length of the longest peak (default: 0.5 times the smallest voxel size, so that it spans its voxel)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l peaks-width -d 'Peak diameter in pixels (default 2; at the target in a perspective view)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l save-scene -d 'Also write the scene that is rendered as a scene file (with the image, all or nothing)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l width -d 'Image width in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l height -d 'Image height in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l scale-factor -d 'Multiply the image\'s width and height by F, keeping its framing: the same figure with more pixels (labels, captions and the colour bar grow with it)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l method -d ' How glyphs are drawn: fixed (ray casting at a fixed step), interval or affine (robust ray casting by range arithmetic), exact (first real root of the ray polynomial; offset 0 only), impostor (bounding spheres), mesh:LEVEL (icosphere) or latlong:N (latitude bands) tessellations. Accepts fixed, interval, affine, exact, impostor, mesh:0 to mesh:7, latlong:N; default exact, or affine with an offset.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l path -d ' Which ray caster runs the method: fragment (proxy boxes) or compute (a compute shader per pixel over screen tiles; exact only). Accepts fragment, compute; default fragment.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l precision -d ' The robust methods\' segment length limit, in pixels at the segment\'s depth. Accepts 0.01 to 64; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l step -d ' The fixed march\'s step, in units of each glyph\'s bounding radius. Accepts 0.001 to 2; default 0.02.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l refine -d ' The refinement of the first sign change along the ray. Accepts bisect:K, secant:K (K = 0 to 16), interp, none; default secant:4.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l color -d ' Glyph colour: direction, magnitude, uniform or sign (positive lobes red, negative ones blue; ray-casting methods only). Accepts direction, magnitude, uniform, sign; default direction.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l magnitude-range -d ' The magnitude colour map\'s range, LOW:HIGH in world units. Accepts two numbers, low below high; default 0 to the largest glyph radius drawn.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l negative -d ' Negative lobes: abs (drawn as |f|) or hide; replaces every glyph set\'s mode. Accepts abs, hide; default the scene\'s (abs for volumes).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l background -d ' Background: none (transparent PNG), a name, #rrggbb or r,g,b (sRGB, 0 to 255, as written in the PNG). Accepts none, dark, black, white, grey, #rrggbb, r,g,b; default dark.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l offset -d ' Isotropic offset added to every glyph, as a fraction of its bounding radius. Accepts a number >= 0; default 0.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l light -d ' Direction towards the light, X,Y,Z in view coordinates (x to the image\'s right, y up, z towards the viewer); the light moves with the camera. Accepts three numbers, not all 0; default 0.35,0.5,1 (above right, in front).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l ambient -d ' Ambient share of the base colour. Accepts 0 to 1; default 0.18.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l specular -d ' Strength of the white specular highlight (0: matte). Accepts 0 to 1; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l shininess -d ' Blinn-Phong exponent of the highlight. Accepts 1 to 1024; default 48.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l samples -d ' Samples per pixel: supersampling draws at 2 or 4 times the width and height, then averages; the depth map stays one ray per pixel centre. Accepts 1, 4, 16; default 1.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l colorbar-label -d 'The colour bar\'s label (default: "radius (data units)" or "radius (world units)")' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l device -d 'Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l frames -d 'Render N frames, write --screenshot (and --capture-window) and exit: a scripted, self-ending run for tests' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l script -d 'Events applied one per frame, comma-separated: resize:WxH, method:NAME, step:S, refine:SPEC, color:MODE, negative:abs|hide|toggle, slice:+N|-N, active:1|2|3, orbit:DX:DY, pan:DX:DY, zoom:F, reset, screenshot, wait. Needs --frames' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l screenshot -d 'PNG for screenshots, rendered headless at the window\'s size and camera: written at the end of a scripted run and by the S key (default glyphcast-view-N.png)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l capture-window -d 'With --frames: also write the last frame as the window showed it (read back from the swapchain)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l frames-in-flight -d 'Frames the window records ahead of the GPU (1 to 4): each waits only for the frame that used its slot before' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l force-basis -d 'Use --basis even where the file records another basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l legacy -d 'The legacy variant of --basis (DIPY\'s legacy=True; MRtrix 0.2 for tournier07)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l nonsymmetric -d '--tensor holds all 3^N entries, row-major, instead of the unique ones'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l perspective -d 'Perspective camera instead of orthographic'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l labels -d 'Write the anatomical directions (L/R, A/P, S/I) at the image\'s edges (of every panel of a montage)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l colorbar -d 'With --color magnitude: append a colour bar of the magnitude range on the right, in a strip of its own (the PNG and the depth map grow by its width; the depth map is NaN there). Values are glyph radii in data units (|f|, or an ellipsoid\'s sqrt(eigenvalue)) when every glyph has the same scale, else in world units'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -l validation -d 'Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand view" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -s o -l output -d 'Output image (PNG)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l depth-out -d 'Also write the ray distance per pixel as a float32 .npy (NaN for misses)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l dpi -d 'The print resolution recorded in the PNG (its pHYs chunk), in pixels per inch: a layout program then places the image at width / DPI inches' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l width -d 'Image width in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l height -d 'Image height in pixels (default: the scene\'s)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l scale-factor -d 'Multiply the image\'s width and height by F, keeping its framing: the same figure with more pixels (labels, captions and the colour bar grow with it)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l method -d ' How glyphs are drawn: fixed (ray casting at a fixed step), interval or affine (robust ray casting by range arithmetic), exact (first real root of the ray polynomial; offset 0 only), impostor (bounding spheres), mesh:LEVEL (icosphere) or latlong:N (latitude bands) tessellations. Accepts fixed, interval, affine, exact, impostor, mesh:0 to mesh:7, latlong:N; default exact, or affine with an offset.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l path -d ' Which ray caster runs the method: fragment (proxy boxes) or compute (a compute shader per pixel over screen tiles; exact only). Accepts fragment, compute; default fragment.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l precision -d ' The robust methods\' segment length limit, in pixels at the segment\'s depth. Accepts 0.01 to 64; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l step -d ' The fixed march\'s step, in units of each glyph\'s bounding radius. Accepts 0.001 to 2; default 0.02.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l refine -d ' The refinement of the first sign change along the ray. Accepts bisect:K, secant:K (K = 0 to 16), interp, none; default secant:4.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l color -d ' Glyph colour: direction, magnitude, uniform or sign (positive lobes red, negative ones blue; ray-casting methods only). Accepts direction, magnitude, uniform, sign; default direction.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l magnitude-range -d ' The magnitude colour map\'s range, LOW:HIGH in world units. Accepts two numbers, low below high; default 0 to the largest glyph radius drawn.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l negative -d ' Negative lobes: abs (drawn as |f|) or hide; replaces every glyph set\'s mode. Accepts abs, hide; default the scene\'s (abs for volumes).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l background -d ' Background: none (transparent PNG), a name, #rrggbb or r,g,b (sRGB, 0 to 255, as written in the PNG). Accepts none, dark, black, white, grey, #rrggbb, r,g,b; default dark.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l offset -d ' Isotropic offset added to every glyph, as a fraction of its bounding radius. Accepts a number >= 0; default 0.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l light -d ' Direction towards the light, X,Y,Z in view coordinates (x to the image\'s right, y up, z towards the viewer); the light moves with the camera. Accepts three numbers, not all 0; default 0.35,0.5,1 (above right, in front).' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l ambient -d ' Ambient share of the base colour. Accepts 0 to 1; default 0.18.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l specular -d ' Strength of the white specular highlight (0: matte). Accepts 0 to 1; default 0.25.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l shininess -d ' Blinn-Phong exponent of the highlight. Accepts 1 to 1024; default 48.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l samples -d ' Samples per pixel: supersampling draws at 2 or 4 times the width and height, then averages; the depth map stays one ray per pixel centre. Accepts 1, 4, 16; default 1.' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l colorbar-label -d 'The colour bar\'s label (default: "radius (data units)" or "radius (world units)")' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l device -d 'Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l save-scene -d 'Also write the demo scene as a scene file' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l stiffness -d 'Show a field of rotated copper crystals as stiffness-tensor glyphs instead'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l colorbar -d 'With --color magnitude: append a colour bar of the magnitude range on the right, in a strip of its own (the PNG and the depth map grow by its width; the depth map is NaN there). Values are glyph radii in data units (|f|, or an ellipsoid\'s sqrt(eigenvalue)) when every glyph has the same scale, else in world units'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -l validation -d 'Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand demo" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l size -d 'Image side in pixels for every scene, 16 to 4096' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l methods -d 'Methods to measure, comma separated: fixed, interval, affine, impostor, mesh:LEVEL, latlong:N' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l steps -d 'March steps of the fixed-step method, comma separated' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l refine -d 'Refinements of the fixed-step method, comma separated' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l markdown -d 'Also write the table as Markdown to this file' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l csv -d 'Also write the table as CSV to this file' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -l device -d 'Vulkan device: part of its name or its index' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand accuracy" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l workload -d 'Generated workload: grid:COUNT:ORDER (fibre tensors) or fodf:COUNT:BAND (SH fODFs)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l sweep -d 'A sweep instead of one measurement: steps (the paper\'s Table 1), scaling (glyph count, order, resolution), table2 (ray casting against tessellation levels 1 to 6, with geometric error), methods (every method on the accuracy suite) or ratios (the default ray caster against the impostor and against tessellation at equal error: grids of orders 4, 8 and 12, and band-8 fODFs) or gpu[:COUNTS] (the GPU report of tools/gpu-report.sh: band-8 fODF fields of 10^3 to 10^6 glyphs at three sizes, every method and both paths; failures are reported, not fatal)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l method -d 'Method of a single measurement: fixed, interval, affine, impostor, mesh:LEVEL or latlong:N' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l path -d 'Ray caster of a single measurement: fragment (proxy boxes) or compute (a compute shader per pixel over screen tiles; exact only)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l frames -d 'Measured frames (after the warm-up), at least 1 (default 20; 3 with --quick)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l warmup -d 'Warm-up frames, not measured (default 3; 1 with --quick)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l width -d 'Image width and height (workloads; a scene keeps its own size unless given)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l height -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l out -d 'Folder for results.csv, results.json and results.md (an existing folder, as for every output)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l save-scene -d 'Also write the measured scene (a workload, at its size) as a scene file, to render or inspect it' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l device -d 'Vulkan device: part of its name or its index' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l accuracy -d 'Also compare a single measurement with the float64 reference'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l quick -d 'Small sweeps and few frames: a check that finishes in a few minutes on lavapipe'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -l scene-arrays -d 'With --save-scene: write each glyph set\'s centers, scales and coefficients as float64 .npy files beside the scene file (SCENE.0.coeffs.npy, ...), which the scene file names: a large scene then reads without parsing JSON numbers'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand bench" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l bval -d 'b-values, FSL format (one row or one column, s/mm^2). Leave out --bval and --bvec for an MRtrix DWI that carries its table (dw_scheme, scanner coordinates)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l bvec -d 'Gradient directions, FSL format (3 rows of n, or n rows of 3), in the frame of --bvec-convention' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l bvec-convention -d 'Frame of --bvec: fsl (voxel axes with x negated when the affine\'s determinant is positive, as FSL and MRtrix read bvecs), voxel (voxel axes as stored) or world (scanner axes). Default: fsl (with a note where it negates x, which DIPY does not)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l order -l lmax -d 'Tensor order (even, 2 to 12), or the highest SH band with --sh or --odf (even, 0 to 12)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -s o -l output -d 'Output: 4D float32 image of coefficients, NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, with the basis in its header)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l odf -d 'Fit a fibre ODF as SH: csd (constrained spherical deconvolution, single shell), msmt (multi-shell multi-tissue CSD: WM fODF to -o, GM and CSF beside it), csa (constant solid angle) or qball' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l basis -d 'SH basis: tournier07 or descoteaux07, or the aliases mrtrix (tournier07), dipy (descoteaux07 legacy, DIPY\'s default) and dipy-new (descoteaux07)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l lambda -d 'Regularisation weight: Laplace-Beltrami for --sh, csa and qball (default 0.006), the non-negativity constraint\'s for csd (default 1; MRtrix\'s -neg_lambda with --csd-algorithm mrtrix)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l csd-algorithm -d 'CSD: which algorithm: mrtrix (MRtrix3\'s dwi2fod csd, the default) or dipy (DIPY\'s ConstrainedSphericalDeconvModel)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l tau -d 'CSD: directions where the fODF is below the threshold are constrained. With --csd-algorithm mrtrix an fODF amplitude (dwi2fod -threshold, default 0); with dipy a fraction of the mean fODF (default 0.1)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l response -d 'CSD: the single-fibre response, MRtrix\'s text format (one row of zonal SH coefficients, as dwi2response writes). Default: estimated from the voxels with FA above --response-fa in the centre of the volume. With msmt: the WM response, one row per shell (b=0 first), with --response-gm and --response-csf' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l response-fa -d 'CSD: FA threshold of the voxels the response is estimated from' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l tensor-order -d 'Stored order of a DTI fit\'s six entries in a NIfTI output: glyphcast (xx, xy, xz, yy, yz, zz, the default; FSL\'s dtifit order), fsl, dipy (xx, xy, yy, xz, yz, zz) or mrtrix (xx, yy, zz, xy, xz, yz). A .mif output is always in MRtrix\'s order. The order is recorded in the file\'s description' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l response-gm -d 'msmt: the GM response, MRtrix\'s multi-shell format (one row per shell, b=0 first, one column); with --response (WM, one row per shell) and --response-csf. Default: all three estimated from the data' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l response-csf -d 'msmt: the CSF response, as --response-gm' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l gm -d 'msmt: the GM image (band 0). Default: beside -o, its name with _gm before the extension (wm.nii.gz: wm_gm.nii.gz)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l csf -d 'msmt: the CSF image (band 0). Default: -o\'s name with _csf' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l mask -d 'Fit only where this 3D NIfTI or MRtrix image is non-zero (same spatial shape as the DWI)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l sh -d 'Fit real spherical harmonics to S/S0 instead of a tensor to the ADCs'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l legacy -d 'The legacy variant of the SH basis (DIPY\'s legacy=True; implied by --basis dipy)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -l quiet -d 'No progress bar and no summary line'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand fit" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -s o -l output -d 'Output: 4D float32 image of 3 N values per voxel, NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l basis -d 'SH basis of the ODF (as render --basis). Default: the one the file records, tournier07 for MRtrix images without a record' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l count -d 'Peaks per voxel (N)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l relative-threshold -d 'Peaks below this fraction of the voxel\'s largest are left out' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l min-separation -d 'Peaks within this angle (degrees) of a larger one are left out' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l legacy -d 'The legacy variant of --basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l force-basis -d 'Use --basis even where the file records another basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -l quiet -d 'No summary line'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand peaks" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -s o -l output -d 'Output folder: written whole or not at all (an earlier set there is replaced, its own files only; a folder holding anything else, or an input, is refused)' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l peaks -d 'Peaks of the ODFs (glyphcast peaks, MRtrix sh2peaks layout) for the peaks mosaic; checked against the ODFs\' grid' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l peaks-frame -d 'Axes of the --peaks directions: voxel or world, as for render --peaks-frame (default: the file\'s own; world for a NIfTI written by MRtrix\'s sh2peaks)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l mask -d 'Mask of the brain (the ODFs\' grid): the cuts, regions and glyphs stay inside it. Default: voxels with finite coefficients and a positive mean amplitude' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l underlay -d 'Anatomical image (FA, T1, colour-FA) drawn under every panel' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l underlay-range -d 'The underlay\'s window LOW:HIGH (default: its 2nd to 98th percentile)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l basis -d 'SH basis of the ODFs, as for render --basis (default: the file\'s record)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l frame -d 'Axes of the coefficients: voxel or world (as for render --frame)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l orientation -d 'radiological (default, as mrview) or neurological' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l panel-size -d 'Side of each panel in pixels, 64 to 4096 (default: 8 pixels per voxel of the volume\'s longest side, 400 to 1024)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l method -d 'How glyphs are drawn, as for render --method (default exact)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l negative -d 'Negative lobes: hide (the default here: fibre ODFs\' negative lobes are fitting noise) or abs' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l samples -d 'Samples per pixel: 1, 4 or 16' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l device -d 'Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE)' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l legacy -d 'The legacy variant of --basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l force-basis -d 'Use --basis even where the file records another basis'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l validation -d 'Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -l quiet -d 'No progress lines'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand qc" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -s o -l output -d 'Output scene file (JSON): one glyph a material, in a row along x' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l summary -d 'Write the elastic extremes and averages (JSON, the input\'s units) and print them as a table: Young\'s modulus with the directions of its extremes, linear compressibility, shear modulus, Poisson\'s ratio, Voigt/Reuss/Hill averages' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l euler -d 'The crystal\'s orientation as Bunge Euler angles in degrees (ZXZ, as MTEX and EBSD write them): g = Rz(phi2) Rx(Phi) Rz(phi1) maps sample to crystal coordinates; the glyphs and numbers are the sample frame\'s' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l rotation -d 'The crystal\'s orientation as a 3 x 3 matrix g (3 lines of 3 numbers) with the meaning of --euler\'s: sample to crystal coordinates' -r -F
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l shear-order -d 'Voigt shear order of the files: 23,13,12 (standard) or 12,13,23' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l surface -d 'The surface the scene draws, its radius in the input\'s units: reynolds (C_ijkl u_i u_j u_k u_l), young (Young\'s modulus E(u)) or compressibility (linear compressibility beta(u), in inverse units; negative where the crystal expands under pressure: render with --color sign). Default: reynolds' -r
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l allow-unstable -d 'Draw and summarise a matrix that is not positive definite (a mechanically unstable crystal, or a mistyped one), which is otherwise refused'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -l symmetric-part -d 'Write the fully symmetric part (15 coefficients) instead of all 81 C_ijkl (the Reynolds glyph: not with --surface)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand stiffness" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand reference" -s h -l help -d 'Print help'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "render" -d 'Render a scene file (docs/scene-format.md) or a volume to a PNG, and optionally a depth map'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "view" -d 'Show a scene file or a volume in a window: orbit, pan and zoom with the mouse, keys for the method, step, refinement, colour, negative lobes and the slice'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "demo" -d 'Render the built-in demo scene (a field of crossing-fibre glyphs)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "accuracy" -d 'Measure every method against the float64 reference on the accuracy suite'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "bench" -d 'GPU timings of the glyph pass: one scene or workload, or a sweep'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "fit" -d 'Fit tensor, SH or fibre-ODF (CSD, CSA, Q-ball) coefficients to a DWI series (writes a 4D NIfTI or MRtrix image)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "peaks" -d 'Find up to N maxima per voxel of an ODF image (MRtrix sh2peaks\' layout)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "qc" -d 'Write one subject\'s quality-control figure set of fibre ODFs into a folder: ODF mosaic, zoomed regions, index.html and the qc.json sidecar'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "stiffness" -d 'Write a scene of stiffness glyphs from Voigt matrices (text, CSV or JSON), and the elastic extremes and averages (--summary)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "reference" -d 'Write the command-line reference into a folder: a Markdown page per command, man pages and shell completions (tools/gen-docs.sh writes docs/reference/)'
complete -c glyphcast -n "__fish_glyphcast_using_subcommand help; and not __fish_seen_subcommand_from render view demo accuracy bench fit peaks qc stiffness reference help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
