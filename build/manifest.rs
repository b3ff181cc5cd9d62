//! glsl/manifest.txt: which tensor layouts get which intersection methods.
use crate::fail;

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Symmetry {
    Symmetric,
    NonSymmetric,
}

pub struct Family {
    pub symmetry: Symmetry,
    pub orders: std::ops::RangeInclusive<u32>,
    pub methods: Vec<String>,
}

pub fn parse_manifest(text: &str) -> Vec<Family> {
    let mut families = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let where_ = format!("glsl/manifest.txt:{}", number + 1);
        let words: Vec<&str> = line.split_whitespace().collect();
        let [kind, symmetry, orders, methods] = words[..] else {
            fail(format!("{where_}: expected `kind symmetry orders methods`"));
        };
        if kind != "tensor" {
            fail(format!("{where_}: unknown kind `{kind}`"));
        }
        let symmetry = match symmetry {
            "symmetric" => Symmetry::Symmetric,
            "nonsymmetric" => Symmetry::NonSymmetric,
            other => fail(format!("{where_}: unknown symmetry `{other}`")),
        };
        let (lo, hi) = orders
            .split_once('-')
            .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
            .unwrap_or_else(|| fail(format!("{where_}: orders must read like 1-12")));
        families.push(Family {
            symmetry,
            orders: lo..=hi,
            methods: methods.split(',').map(str::to_owned).collect(),
        });
    }
    families
}
