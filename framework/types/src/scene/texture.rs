use std::path::PathBuf;

use glam::Vec3;

/// An RGB image in linear floating point, looked up by texture coordinates.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Texture {
    /// File the texture was loaded from.
    pub path: PathBuf,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels row by row, top row first, linear RGB.
    pub texels: Vec<Vec3>,
}

impl Texture {
    /// A generated texture of `width × height` texels (at least 1 each), texel `(i, j)` (column
    /// `i`, row `j` from the top) being `texel(i, j)`; `name` stands for its file in messages.
    pub fn from_fn(name: &str, width: u32, height: u32, texel: impl Fn(u32, u32) -> Vec3) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let texels = (0..height)
            .flat_map(|j| (0..width).map(move |i| (i, j)))
            .map(|(i, j)| texel(i, j))
            .collect();
        Self {
            path: PathBuf::from(name),
            width,
            height,
            texels,
        }
    }

    /// A checkerboard of `squares × squares` squares of `texels_per_square²` texels each,
    /// alternating `light` and `dark` (light in the top-left corner).
    pub fn checkerboard(squares: u32, texels_per_square: u32, light: Vec3, dark: Vec3) -> Self {
        let n = texels_per_square.max(1);
        let size = squares.max(1) * n;
        Self::from_fn(
            &format!("<checkerboard {squares}×{squares}>"),
            size,
            size,
            |i, j| {
                if (i / n + j / n) & 1 == 0 {
                    light
                } else {
                    dark
                }
            },
        )
    }

    /// A `width × height` colour gradient, linear in the texel indices: red grows to the
    /// right from 0 to 1, green from the bottom row (0) to the top row (1), blue is ¼.
    pub fn gradient(width: u32, height: u32) -> Self {
        let (w, h) = (width.max(1), height.max(1));
        let step = |k: u32, n: u32| {
            if n > 1 {
                k as f32 / (n - 1) as f32
            } else {
                0.0
            }
        };
        Self::from_fn(&format!("<gradient {w}×{h}>"), w, h, |i, j| {
            Vec3::new(step(i, w), step(h - 1 - j, h), 0.25)
        })
    }

    /// The texel in column `i` (from the left) and row `j` (from the top); both must be in
    /// range (`i < width`, `j < height`).
    #[inline]
    pub fn texel(&self, i: u32, j: u32) -> Vec3 {
        self.texels[(j as usize) * (self.width as usize) + i as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkerboard_alternates_by_square() {
        let (light, dark) = (Vec3::ONE, Vec3::ZERO);
        let t = Texture::checkerboard(4, 2, light, dark);
        assert_eq!((t.width, t.height), (8, 8));
        assert_eq!(t.texel(0, 0), light);
        assert_eq!(t.texel(1, 1), light);
        assert_eq!(t.texel(2, 0), dark);
        assert_eq!(t.texel(2, 2), light);
        assert_eq!(t.texel(7, 0), dark);
    }

    #[test]
    fn gradient_is_linear_in_the_texel_indices() {
        let t = Texture::gradient(5, 3);
        assert_eq!(t.texel(0, 2), Vec3::new(0.0, 0.0, 0.25));
        assert_eq!(t.texel(4, 0), Vec3::new(1.0, 1.0, 0.25));
        assert_eq!(t.texel(2, 1), Vec3::new(0.5, 0.5, 0.25));
        // A single texel has no gradient to show; empty sizes become 1.
        assert_eq!(
            Texture::gradient(0, 0).texels,
            vec![Vec3::new(0.0, 0.0, 0.25)]
        );
    }
}
