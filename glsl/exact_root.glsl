// The exact method's root isolation (raycast_exact.frag's steps 1 to 4): the ray polynomial
// of the glyph, its first real root on a chord of the bounding sphere, and the sampled
// centre zone. Shared by the fragment shader (raycast_exact.frag) and the compute ray
// caster (raycast_exact.comp). Include after glyph_ray.glsl (inside(), glyph_set) and the
// glyph function (glyph_c).
// The generated arithmetic divides by the binomials C(2n + 2, k) as float32 literals, exact
// while they stay below 2^24: C(26, 13) = 10,400,600 at order 12, but C(28, 14) =
// 40,116,600 at order 13.
#ifndef GLYPH_ORDER_MACRO
#error "exact_root.glsl needs glyph_function.glsl first"
#elif GLYPH_ORDER_MACRO > 12
#error "the exact method's binomials are exact in float32 only up to order 12"
#endif

const int N = int(GLYPH_ORDER);
#if defined(GLYPHCAST_PLANE)
// The plane glyph r = 1/λ, λ² − T λ + D = 0 (build/table.rs compiles this variant for
// D's layout, order 6; T has order 4 and follows D in glyph_c). With λ = 1/|q| and the
// forms T(q), D(q) of the normalised frame, |q|⁴ − T(q) |q| + D(q) = 0 on both roots'
// surfaces, and squared, F = T(q)² |q|² − (|q|⁴ + D(q))², of degree 12: its other
// factor |q|⁴ + T |q| + D has no zero, as T and D are positive. F is positive between
// the two surfaces and negative inside the inner one and outside the outer one; each
// root is kept or passed over by its branch (plane_root_kept), as the hide filter does.
// The k of the Newton steps' G = F / |q|^(2k): G = T(q^)² |q|² − (1 + D(q^) |q|²)².
const int NT = 4;
const int D = 12;
const int G_EXPONENT = 4;
#elif defined(GLYPHCAST_RATIO)
// The ratio glyph r = |λ/Q|, λ² − T λ + D = 0 (build/table.rs compiles this variant for
// D's layout, order 6; T and Q have order 4 and follow D in glyph_c). With r = |q| and the
// sign σ of λ/Q (Q > 0), λ = σ |q| Q(q^), so |q|² Q² − σ |q| T Q + D = 0 at unit q^, and
// for the forms of q, |q| (Q(q)² + D(q)) = σ Q(q) T(q); squared,
// F = Q(q)² T(q)² − |q|² (Q(q)² + D(q))², of degree 18, holds both branches (σ = ±1).
// F is negative outside both surfaces; each root is kept or passed over by its branch
// (ratio_root_kept). The k of the Newton steps' G = F / |q|^(2k): G =
// |q|² Q(q^)² T(q^)² − (|q|² Q(q^)² + D(q^))².
const int NT = 4;
const int D = 18;
const int G_EXPONENT = 7;
#elif defined(GLYPHCAST_RECIPROCAL)
// The reciprocal glyph r = 1/|f| (build/table.rs compiles this variant for even orders):
// inside |f(q)| < |q|^(n-1), so F = (q . q)^(n-1) - f(q)^2, of degree 2n, is positive
// inside as the polynomial glyph's F is. The power n - 1 of q . q and its highest set
// bit (n - 1 is 1 to 11), and the k of the Newton steps' G = F / |q|^(2k).
const int D = 2 * N;
const int POWER = N - 1;
const int POWER_TOP_BIT = POWER >= 8 ? 3 : (POWER >= 4 ? 2 : (POWER >= 2 ? 1 : 0));
const int G_EXPONENT = N - 1;
#else
const int D = 2 * N + 2;
// The power n + 1 of q . q in F, and its highest set bit (n + 1 is 2 to 13).
const int POWER = N + 1;
const int POWER_TOP_BIT = POWER >= 8 ? 3 : (POWER >= 4 ? 2 : 1);
#endif
// The chord is that of the bounding sphere enlarged by 2^-10, so that F < 0 at both of its
// ends even for a glyph that touches its bound (g <= -2^-10 there).
const float CHORD_RADIUS = 1.0 + 1.0 / 1024.0;
// |q|^D >= 2^-100 outside this radius, which leaves F and its Bernstein coefficients
// 2^26 of float32's normal range: 0.07 at order 12, 0.021 at order 8, 0.001 at order 4.
const float CENTRE_RADIUS = exp2(-100.0 / float(D));
// g samples across the centre zone (at most 2 CENTRE_RADIUS long).
const int CENTRE_SAMPLES = 64;
// Subdivision depth (pieces of 2^-20 of a segment) and budget of pieces per segment.
const int MAX_LEVEL = 20;
const int MAX_NODES = 64;
const int NEWTON_STEPS = 40;
const int ILLINOIS_STEPS = 8;

float ray_p[N + 1];        // f(mid + tau d) = sum_k ray_p[k] tau^k
float segment_p[N + 1];    // f(s a + t b) = sum_i segment_p[i] s^(n-i) t^i
float segment_f[D + 1];    // F on the segment, Bernstein basis
// segment_p and segment_f of the chord's two halves (0: before mid, 1: after).
float half_p0[N + 1];
float half_p1[N + 1];
float half_f0[D + 1];
float half_f1[D + 1];
float node_f[D + 1];       // F on the current piece of the segment, Bernstein basis
#if defined(GLYPHCAST_PLANE) || defined(GLYPHCAST_RATIO)
float ray_t[N + 1];        // T(mid + tau d), degree NT (the rest 0)
float segment_t[N + 1];    // T(s a + t b) = sum_i segment_t[i] s^(NT-i) t^i
#endif
#ifdef GLYPHCAST_PLANE
float half_t0[N + 1];
float half_t1[N + 1];
#endif
#ifdef GLYPHCAST_RATIO
float ray_q[N + 1];        // Q(mid + tau d), degree NT (the rest 0)
float segment_q[N + 1];    // Q(s a + t b), as segment_t
#endif

// The traversal keeps F on the part of the half not yet visited, [rest_start, 1], in
// rest_f. The next piece [rest_start, u1] is its left part at s = (u1 - rest_start) /
// (1 - rest_start): one de Casteljau pass gives the piece (node_f) and the part after it
// (split_f), the rest once the piece is done. Consecutive pieces then share their end
// coefficient exactly, and a piece costs one pass instead of the two that cut it out of
// the whole half.
float rest_f[D + 1];
float split_f[D + 1];

// The fixed-size arithmetic on these arrays, written out by the generator
// (build/exact_kernels.rs) for this shader's N, D and variant, every index a literal:
// ray_polynomial, the ray's polynomial(s) by Horner's scheme on linear
// polynomials in tau, which is exact algebra (each coefficient is rounded relative to
// the sizes of its own terms, ~|mid|^(n-k) |d|^k, so the small ones near the centre stay
// accurate); segment_polynomials, each half's p re-expanded about its end nearer mid (a
// Taylor shift), turned into the Bernstein basis and into F = p^2 (s + t)^2 - (q . q)^(n+1)
// (or the variant's F) as a form of degree D, (q . q)^(n+1) by squaring with every
// coefficient a sum of positive terms; split_rest, one de Casteljau pass; sign_changes_of,
// Descartes' bound in the Bernstein basis; node_newton, the value and Newton step of the
// piece's polynomial in one Horner pass, mirrored beyond x = 1/2 so that no power
// overflows; polygon_crossing, where the control polygon first crosses zero;
// half_p_sign, f's sign on a half for the hide filter (and a plane glyph's T there,
// half_t_values).
#include "exact_kernels.glsl"

// Sign changes of node_f, zeros skipped: an upper bound on the number of roots of F on
// the piece, of the same parity (Descartes' rule in the Bernstein basis).
int sign_changes() {
    return sign_changes_of(node_f);
}

// node_newton gives the value (its sign) and Newton step v / v' of the piece's
// polynomial at x in (0, 1), in O(D): v = (1 - y)^D P(y / (1 - y)), P = sum C(D, k) b_k
// r^k, with y = x and b = node_f for x <= 1/2, or the mirror image y = 1 - x and b
// reversed, so that the powers never overflow and need not be formed (one Horner pass
// for every lane); dv/dy = (1 - y)^(D-2) (P' - D (1 - y) P), and dx = -dy in the mirror.

// The root in (0, 1) of the piece's polynomial, whose end values differ in sign; the piece
// spans tau = tau_at_0 + x tau_per_x. Newton starts where the control polygon first
// crosses zero and steps on G = F / |q|^(2n) = f(q^)^2 - |q|^2 rather than on F: G is
// O(1) and nearly linear where F spans the |q|^(2n) orders of magnitude between the centre
// and the sphere, which slows Newton on F to a crawl. With R = |q|^2 = |mid|^2 + tau^2 |d|^2,
// G / G' = F / (F' - n F R' / R). Bracketed: bisection when a step leaves the bracket or
// fails to halve. Measured: 3 to 5 steps, at most ~12, to float resolution.
float node_root(float tau_at_0, float tau_per_x, float mid2, float d2) {
    float lo = 0.0;
    float hi = 1.0;
    bool lo_positive = node_f[0] > 0.0;
    float x = clamp(polygon_crossing(lo_positive), 1e-6, 1.0 - 1e-6);
    float step_before = 1.0;
    for (int i = 0; i < NEWTON_STEPS; ++i) {
        float value, step_f;
        node_newton(x, value, step_f);
        if ((value > 0.0) == lo_positive) {
            lo = x;
        } else {
            hi = x;
        }
        float tau = tau_at_0 + x * tau_per_x;
        float r = mid2 + tau * tau * d2;
        float r_slope = 2.0 * d2 * tau * tau_per_x;
#if defined(GLYPHCAST_RECIPROCAL) || defined(GLYPHCAST_PLANE) || defined(GLYPHCAST_RATIO)
        float step = step_f / (1.0 - float(G_EXPONENT) * r_slope / r * step_f);
#else
        float step = step_f / (1.0 - float(N) * r_slope / r * step_f);
#endif
        // Done when the step is below float resolution (about 2 ulps of x).
        float resolution = 1.2e-7 * max(x, 0.25);
        if (abs(step) <= resolution) {
            x = clamp(x - step, lo, hi);
            break;
        }
        float next = x - step;
        // Newton only while it stays in the bracket and at least halves its step.
        if (!(next > lo && next < hi && abs(step) < 0.5 * step_before)) {
            next = 0.5 * (lo + hi);
        }
        step_before = abs(next - x);
        bool stalled = next == x;
        x = next;
        if (stalled || hi - lo <= resolution) {
            break;
        }
    }
    return x;
}

bool hide_negative() {
#if defined(GLYPHCAST_PLANE) || defined(GLYPHCAST_RATIO)
    // The word names a plane or ratio glyph's root; it has no negative lobes.
    return false;
#else
    return glyph_set.hide_negative == NEGATIVE_HIDE;
#endif
}

#ifdef GLYPHCAST_PLANE
// Whether the root at u on a half, where |q|² = length2, is kept: the plane glyph's
// root of the set's branch. The larger root λ = 1/|q| has
// 2 λ ≥ T(q^), that is 2 |q|³ ≥ T(q), with T(q) from the half's form of degree NT.
bool root_kept(int half_index, float u, float length2) {
    float r = u / (1.0 - u);
    float w = (1.0 - u) / u;
    float from_start;
    float from_end;
    half_t_values(half_index, r, w, from_start, from_end);
    float s4 = pow(1.0 - u, 4.0);
    float t4 = pow(u, 4.0);
    float trace = u <= 0.5 ? from_start * s4 : from_end * t4;
    bool larger = 2.0 * length2 * sqrt(length2) >= trace;
    return larger == (glyph_set.hide_negative == PLANE_MIN);
}
#endif

#ifdef GLYPHCAST_RATIO
// Whether the root at q is kept: the ratio glyph's root of the set's branch. The larger
// root λ = σ |q| Q(q^) has 2 λ ≥ T(q^).
bool ratio_root_kept(vec3 q) {
    float len = max(length(q), 1e-30);
    vec3 u = q / len;
    float qu = ratio_q(u);
    float t = plane_t(u);
    float sigma = ratio_sign(len * len * qu * qu + glyph_f(u), len * qu * t);
    bool larger = 2.0 * sigma * len * qu >= t;
    return larger == (glyph_set.hide_negative == RATIO_MAX);
}
#endif

// The traversal of the pieces of both halves in ray order (step 3). One loop visits the
// pieces of both halves, and the Newton refinement and the hide filter run after it, not
// in its body: lavapipe runs every instruction of a loop body for every fragment of a
// SIMD batch, its lanes masked, so the body's length times the batch's largest number of
// visits is what a fragment pays.
int visit_half;       // the half being traversed; 2: both done
int visit_level;      // the piece is [index, index + 1] 2^-level of the half
uint visit_index;
int visit_count;      // pieces visited in this half, against MAX_NODES
float rest_start;     // where the part of the half not yet visited starts
bool half1_valid;
// Where a half's budget of pieces ran out (the rest is sampled), else its end.
bool exhausted0;
bool exhausted1;
float leftover0;
float leftover1;

// Sign changes of each half's F as a whole (the root of its tree), counted before the
// traversal: a half without any is passed over and one with two or more starts at its
// two halves, so that no pass of the traversal's loop is spent on the whole half (on
// lavapipe every pass costs the batch's lanes the loop's whole body).
int changes0;
int changes1;

// Starts the traversal of half h (0 or 1), or of the next one that has sign changes;
// visit_half 2 when none is left.
void enter_half(int h) {
    if (h == 0 && changes0 == 0) {
        h = 1;
    }
    if (h == 1 && (!half1_valid || changes1 == 0)) {
        h = 2;
    }
    visit_half = h;
    visit_level = (h == 0 ? changes0 : changes1) >= 2 ? 1 : 0;
    visit_index = 0u;
    visit_count = 0;
    rest_start = 0.0;
    rest_f = h == 0 ? half_f0 : half_f1;
}

void next_half() {
    enter_half(visit_half + 1);
}

// On to the piece after the one just visited ([rest_start, u1]), in ray order, or to the
// next half.
void next_piece(float u1) {
    rest_f = split_f;
    rest_start = u1;
    int up = findLSB(~visit_index);  // the right children to climb out of
    visit_index >>= uint(up);
    visit_level -= up;
    visit_index += 1u;
    if (visit_level == 0) {
        next_half();
    }
}

// The next piece [rest_start, u1] that isolates a root (node_f holds it, its ends differ
// in sign); false when none is left.
bool next_candidate(float lo0, float hi0, float lo1, float hi1, out float u1) {
    u1 = 1.0;
    for (int step = 0; step < 2 * MAX_NODES + 2; ++step) {
        if (visit_half < 2 && visit_count >= MAX_NODES) {
            // Out of budget (never seen in the tests): the rest of the half is sampled.
            if (visit_half == 0) {
                exhausted0 = true;
                leftover0 = mix(lo0, hi0, rest_start);
            } else {
                exhausted1 = true;
                leftover1 = mix(lo1, hi1, rest_start);
            }
            next_half();
        }
        if (visit_half >= 2) {
            return false;
        }
        u1 = float(visit_index + 1u) * exp2(-float(visit_level));
        split_rest(u1 >= 1.0 ? 1.0 : (u1 - rest_start) / (1.0 - rest_start));
        visit_count += 1;
        int changes = sign_changes();
        if (changes >= 2 && visit_level < MAX_LEVEL) {
            visit_level += 1;
            visit_index *= 2u;
            continue;
        }
        // An odd number of roots on the piece: one, when it is fully split.
        if (changes >= 1 && (node_f[0] > 0.0) != (node_f[D] > 0.0)) {
            return true;
        }
        next_piece(u1);
    }
    return false;
}

// Sampling passes at most: two stretches and the regula falsi after a sign change.
const int MARCH_PASSES = 2 * (CENTRE_SAMPLES + 1) + ILLINOIS_STEPS;

// After the first sampled stretch (empty or sampled without a crossing, ending in
// `state`): the crossing at the junction with half 1, the root found in half 1, or the
// rest of half 1 that its budget left (second stretch; its start state unknown), else
// no crossing.
void after_first_stretch(inout int state, bool found, float found_tau, bool start1_inside,
                         float lo1, float hi1, inout int outcome, inout float tau,
                         inout bool second, inout float march_lo, inout float march_hi) {
    if (half1_valid && state >= 0 && start1_inside != (state == 1)) {
        tau = lo1;
        outcome = 1;
    } else if (found) {
        tau = found_tau;
        outcome = 1;
    } else if (exhausted1 && leftover1 < hi1) {
        second = true;
        march_lo = leftover1;
        march_hi = hi1;
        state = -1;
    } else {
        outcome = 0;
    }
}

#ifdef GLYPHCAST_SHADOWS
// Set for a shadow ray (raycast_exact.frag): it asks only whether the ray meets the
// glyph, not where first, so that a root is not refined, and a half whose F has opposite
// signs at its ends holds a root (F is continuous) that need not be isolated. Under
// negative: hide a root counts only on a shown lobe, so roots are isolated as for the
// camera's rays.
bool shadow_ray_only = false;
#endif

// First crossing along q = mid + tau d, tau in [tau_start, tau_end] (within [-1, 1], the
// box's part of the chord): by subdivision on the half before mid up to -tau_c, sampled in
// the centre zone [-tau_c, tau_c] (empty when the ray passes farther than CENTRE_RADIUS
// from the centre), by subdivision on the half after mid from tau_c on. Both halves are
// traversed first; the centre zone and what a spent budget left are sampled after, and a
// crossing there wins over one in the second half.
bool first_crossing(vec3 mid, vec3 d, float tau_start, float tau_end, out float tau) {
    float a = dot(mid, mid);
    float r2 = CENTRE_RADIUS * CENTRE_RADIUS;
    float tau_c = a < r2 ? sqrt(r2 - a) / length(d) : 0.0;
    tau = tau_start;
    float lo0 = max(tau_start, -1.0);
    float hi0 = min(tau_end, -tau_c);
    float lo1 = max(tau_start, tau_c);
    float hi1 = min(tau_end, 1.0);
    bool half0_valid = lo0 < hi0;
    half1_valid = lo1 < hi1;
    segment_polynomials(mid, d, lo0, hi0);
    half_f0 = segment_f;
    half_p0 = segment_p;
#ifdef GLYPHCAST_PLANE
    half_t0 = segment_t;
#endif
    segment_polynomials(mid, d, lo1, hi1);
    half_f1 = segment_f;
    half_p1 = segment_p;
#ifdef GLYPHCAST_PLANE
    half_t1 = segment_t;
#endif
    bool hide = hide_negative();
    // Inside at the end of half 0 and at the start of half 1.
    bool end0_inside = half_f0[D] > 0.0 && (!hide || half_p0[N] > 0.0);
    bool start1_inside = half_f1[0] > 0.0 && (!hide || half_p1[0] > 0.0);

    exhausted0 = false;
    exhausted1 = false;
    leftover0 = hi0;
    leftover1 = hi1;
    changes0 = half0_valid ? sign_changes_of(half_f0) : 0;
    changes1 = sign_changes_of(half_f1);
#ifdef GLYPHCAST_SHADOWS
    bool any_root = shadow_ray_only && !hide;
    if (any_root && ((half0_valid && (half_f0[0] > 0.0) != (half_f0[D] > 0.0))
                     || (half1_valid && (half_f1[0] > 0.0) != (half_f1[D] > 0.0)))) {
        return true;
    }
#endif
    enter_half(0);
    bool found = false;
    int found_half = 0;
    // Each root that the hide filter rejects (the edge of a hidden lobe) costs one round;
    // the traversal goes on after it. Every round visits a piece, so the bound is never
    // reached.
    for (int round = 0; round < 2 * MAX_NODES + 2; ++round) {
        float u1;
        if (!next_candidate(lo0, hi0, lo1, hi1, u1)) {
            break;
        }
#ifdef GLYPHCAST_SHADOWS
        if (any_root) {
            return true;  // a root is isolated on the piece; where does not matter
        }
#endif
        float lo = visit_half == 0 ? lo0 : lo1;
        float hi = visit_half == 0 ? hi0 : hi1;
        float u0 = rest_start;
        float u = mix(u0, u1, node_root(mix(lo, hi, u0), (hi - lo) * (u1 - u0), a, dot(d, d)));
#if defined(GLYPHCAST_PLANE)
        float tau_u = mix(lo, hi, u);
        if (root_kept(visit_half, u, a + tau_u * tau_u * dot(d, d))) {
#elif defined(GLYPHCAST_RATIO)
        if (ratio_root_kept(mid + mix(lo, hi, u) * d)) {
#else
        if (!hide || half_p_sign(visit_half, u) > 0.0) {
#endif
            found = true;
            found_half = visit_half;
            tau = mix(lo, hi, u);
            break;
        }
        next_piece(u1);
    }
    if (found && found_half == 0) {
        return true;
    }
    float found_tau = tau;
    // Sampled after half 0: what its budget left, then the centre zone; after half 1, what
    // its budget left. `state` is the inside state where the sampling starts (-1: unknown).
    int state = half0_valid && !exhausted0 ? (end0_inside ? 1 : 0) : -1;
    float march_lo = leftover0;
    float march_hi = hi0;
    float centre_lo = max(tau_start, -tau_c);
    float centre_hi = min(tau_end, tau_c);
    if (centre_lo < centre_hi) {
        march_lo = exhausted0 ? march_lo : centre_lo;
        march_hi = centre_hi;
    }
    // One loop, one evaluation of g per pass, for the sampling of both stretches and the
    // regula falsi after a sign change: on lavapipe a fragment that samples nothing
    // still pays one pass of every loop it meets, nested loops included.
    int outcome = -1;  // 1: crossing at tau; 0: none
    bool second = false;
    if (!(march_lo < march_hi)) {
        after_first_stretch(state, found, found_tau, start1_inside, lo1, hi1, outcome, tau,
                            second, march_lo, march_hi);
    }
    int k = 0;            // sample index on the stretch
    bool refining = false;
    int refined = 0;
    float t_prev = march_lo;
    float g_prev = 0.0;
    float t0 = 0.0, g0 = 0.0, t1 = 0.0, g1 = 0.0;
    int stuck = 0;
    for (int step = 0; step < MARCH_PASSES && outcome < 0; ++step) {
        float t = refining ? t0 + (t1 - t0) * (g0 / (g0 - g1))
                           : mix(march_lo, march_hi, float(k) / float(CENTRE_SAMPLES));
        float g = inside(mid + t * d);
        if (refining) {
            // Regula falsi, Illinois variant: halve the weight of an end that stays put.
            if ((g > 0.0) == (g1 > 0.0)) {
                t1 = t; g1 = g;
                if (stuck == 1) { g0 *= 0.5; }
                stuck = 1;
            } else {
                t0 = t; g0 = g;
                if (stuck == -1) { g1 *= 0.5; }
                stuck = -1;
            }
            refined += 1;
            if (refined == ILLINOIS_STEPS) {
                tau = t0 + (t1 - t0) * (g0 / (g0 - g1));
                outcome = 1;
            }
        } else if (k == 0 && state >= 0 && (g > 0.0) != (state == 1)) {
            tau = march_lo;
            outcome = 1;
        } else if (k > 0 && (g > 0.0) != (g_prev > 0.0)) {
            refining = true;
            t0 = t_prev; g0 = g_prev; t1 = t; g1 = g;
        } else if (k == CENTRE_SAMPLES) {
            state = g > 0.0 ? 1 : 0;
            if (second) {
                outcome = 0;
            } else {
                after_first_stretch(state, found, found_tau, start1_inside, lo1, hi1,
                                    outcome, tau, second, march_lo, march_hi);
                k = -1;
            }
        }
        t_prev = t;
        g_prev = g;
        k += 1;
    }
    return outcome == 1;
}
