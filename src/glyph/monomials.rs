//! Monomials of a homogeneous polynomial of degree n in (x, y, z), in the coefficient
//! order of the scene format, shared by the CPU reference and by build.rs (which
//! includes this file with `#[path]`), so the generated shaders and the float64 code
//! can never disagree on the order or the multiplicities.
//!
//! Monomial k of degree n corresponds to the sorted index tuple k of the symmetric
//! tensor (0 = x, 1 = y, 2 = z), in lexicographic order of those tuples; its powers
//! (a, b, c) count the 0s, 1s and 2s. The multiplicity n!/(a! b! c!) is the number of
//! index orderings of that tuple (the paper's Eq. 5 weight).

/// Powers (a, b, c) of x, y, z for one monomial x^a y^b z^c.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Monomial {
    /// Power of x.
    pub a: u32,
    /// Power of y.
    pub b: u32,
    /// Power of z.
    pub c: u32,
}

/// Number of unique coefficients of a symmetric tensor of order n: (n+1)(n+2)/2.
pub const fn symmetric_count(order: u32) -> usize {
    ((order + 1) * (order + 2) / 2) as usize
}

/// Number of coefficients of a non-symmetric tensor of order n: 3^n.
pub const fn nonsymmetric_count(order: u32) -> usize {
    3usize.pow(order)
}

/// The monomials of degree `order`, in the scene format's symmetric coefficient order:
/// lexicographic order of the sorted index tuples 0..0 (x^n) to 2..2 (z^n).
pub fn monomials(order: u32) -> Vec<Monomial> {
    let mut out = Vec::with_capacity(symmetric_count(order));
    // Sorted tuples in lexicographic order: first by the number of 0s descending,
    // then by the number of 1s descending.
    for a in (0..=order).rev() {
        for b in (0..=order - a).rev() {
            out.push(Monomial {
                a,
                b,
                c: order - a - b,
            });
        }
    }
    out
}

/// n! / (a! b! c!): the number of index orderings of the monomial's tuple.
pub fn multiplicity(m: Monomial) -> u64 {
    let fact = |k: u32| (1..=k as u64).product::<u64>();
    fact(m.a + m.b + m.c) / (fact(m.a) * fact(m.b) * fact(m.c))
}

/// Index of monomial (a, b, c) of degree `order` within `monomials(order)`.
pub fn monomial_index(order: u32, m: Monomial) -> usize {
    // Tuples with more 0s come first: for a' > a there are (order - a' + 1) of them.
    let before_a: u32 = (m.a + 1..=order).map(|ap| order - ap + 1).sum();
    (before_a + (order - m.a - m.b)) as usize
}

/// For a non-symmetric tensor of order n stored row-major (i1 most significant), the
/// monomial that entry `flat` multiplies in f(u) = sum T[i1..in] u_i1 ... u_in.
pub fn nonsymmetric_entry_monomial(order: u32, flat: usize) -> Monomial {
    let mut counts = [0u32; 3];
    let mut rest = flat;
    for _ in 0..order {
        counts[rest % 3] += 1;
        rest /= 3;
    }
    Monomial {
        a: counts[0],
        b: counts[1],
        c: counts[2],
    }
}
