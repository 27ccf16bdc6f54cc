//! A small reader and writer of NumPy's `.npy` format (version 1 to 3) for two-dimensional arrays:
//! depth images of `float32`/`float64` metres or `uint16` units, and label images of unsigned or
//! signed integers. Enough for `numpy.save(path, array)` and nothing more: no pickled objects, no
//! Fortran order.
//!
//! A file is the magic `\x93NUMPY`, a version, the header's length, a Python dict literal
//! `{'descr': '<f4', 'fortran_order': False, 'shape': (720, 1280), }`, then the data row-major.

use crate::error::{Error, Result};

/// The values of a `.npy` file.
#[derive(Clone, Debug, PartialEq)]
pub enum NpyData {
    /// `float32` or `float64`, as `f32`.
    Float(Vec<f32>),
    /// `uint16`.
    Unsigned16(Vec<u16>),
    /// Any other integer type, as `u32` (negative values refused).
    Integer(Vec<u32>),
}

/// A two-dimensional array read from a `.npy` file.
#[derive(Clone, Debug, PartialEq)]
pub struct Npy {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub columns: usize,
    /// The values, row-major.
    pub data: NpyData,
}

impl Npy {
    /// The array as a depth image: float metres or uint16 units. `source` and `field` name it in
    /// the error (say `"perceive"` and `"--depth"`).
    ///
    /// # Errors
    /// Other integers, which are no depth.
    pub fn depth(&self, source: &str, field: &str) -> Result<super::Depth<'_>> {
        match &self.data {
            NpyData::Float(values) => Ok(super::Depth::Metres(values)),
            NpyData::Unsigned16(values) => Ok(super::Depth::Units(values)),
            NpyData::Integer(_) => Err(Error::field(
                source,
                field,
                "depth must be float32/float64 metres or uint16 units",
            )),
        }
    }

    /// The array as instance labels: integers, 0 for none. `source` and `field` name it in the
    /// error.
    ///
    /// # Errors
    /// Floats, which are no labels.
    pub fn labels(&self, source: &str, field: &str) -> Result<Vec<u32>> {
        match &self.data {
            NpyData::Integer(values) => Ok(values.clone()),
            NpyData::Unsigned16(values) => Ok(values.iter().map(|&l| u32::from(l)).collect()),
            NpyData::Float(_) => Err(Error::field(
                source,
                field,
                "labels must be integers, one id per pixel, 0 for none",
            )),
        }
    }
}

fn bad(source: &str, reason: impl Into<String>) -> Error {
    Error::field(source, "npy", reason.into())
}

/// The value of `key` in the header dict, as written (`'<f4'`, `False`, `(720, 1280)`).
fn header_value<'a>(header: &'a str, key: &str) -> Option<&'a str> {
    let start = header.find(&format!("'{key}'"))? + key.len() + 2;
    let rest = header[start..].trim_start().strip_prefix(':')?.trim_start();
    let end = if rest.starts_with('(') {
        rest.find(')')? + 1
    } else {
        rest.find([',', '}'])?
    };
    Some(rest[..end].trim())
}

/// Reads a two-dimensional `.npy` array; `source` names the file in errors.
///
/// # Errors
/// An [`Error::InvalidField`] naming the file when it is not a `.npy` file, is Fortran-ordered, is
/// not two-dimensional, has a type other than floats or integers, is cut short, or holds negative
/// labels.
pub fn read_npy(bytes: &[u8], source: &str) -> Result<Npy> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err(bad(source, "not a .npy file (no \\x93NUMPY magic)"));
    }
    let (length, start) = match bytes[6] {
        1 => (usize::from(u16::from_le_bytes([bytes[8], bytes[9]])), 10),
        2 | 3 if bytes.len() >= 12 => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
        version => return Err(bad(source, format!(".npy version {version} is not known"))),
    };
    let header = bytes
        .get(start..start + length)
        .and_then(|h| std::str::from_utf8(h).ok())
        .ok_or_else(|| bad(source, "the header is cut short or not text"))?;
    let descr = header_value(header, "descr")
        .map(|d| d.trim_matches(['\'', '"']))
        .ok_or_else(|| bad(source, "the header has no 'descr'"))?;
    if header_value(header, "fortran_order") == Some("True") {
        return Err(bad(
            source,
            "Fortran order is not read; save with numpy.ascontiguousarray",
        ));
    }
    let shape: Vec<usize> = header_value(header, "shape")
        .ok_or_else(|| bad(source, "the header has no 'shape'"))?
        .trim_matches(['(', ')'])
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse::<usize>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad(source, "the shape is not a tuple of sizes"))?;
    let [rows, columns] = shape[..] else {
        return Err(bad(
            source,
            format!("an image must have two dimensions, this has shape {shape:?}"),
        ));
    };
    let body = &bytes[start + length..];
    let little = !descr.starts_with('>');
    let kind = descr.trim_start_matches(['<', '>', '|', '=']);
    let size: usize = kind[1..]
        .parse()
        .map_err(|_| bad(source, format!("type `{descr}` is not read")))?;
    let count = rows * columns;
    if body.len() < count * size {
        return Err(bad(
            source,
            format!(
                "{rows}×{columns} values of {size} bytes need {} bytes, the file has {}",
                count * size,
                body.len()
            ),
        ));
    }
    let word = |k: usize| -> u64 {
        let mut value = 0_u64;
        for b in 0..size {
            let byte = u64::from(body[k * size + if little { b } else { size - 1 - b }]);
            value |= byte << (8 * b);
        }
        value
    };
    let data = match (kind.as_bytes()[0], size) {
        (b'f', 4) => NpyData::Float((0..count).map(|k| f32::from_bits(word(k) as u32)).collect()),
        (b'f', 8) => NpyData::Float((0..count).map(|k| f64::from_bits(word(k)) as f32).collect()),
        (b'u', 2) => NpyData::Unsigned16((0..count).map(|k| word(k) as u16).collect()),
        (b'u', 1 | 4 | 8) => NpyData::Integer(
            (0..count)
                .map(|k| u32::try_from(word(k)).map_err(|_| bad(source, "a label above 2³² − 1")))
                .collect::<Result<_>>()?,
        ),
        (b'i', 1 | 2 | 4 | 8) => {
            let shift = 64 - 8 * size as u32;
            NpyData::Integer(
                (0..count)
                    .map(|k| {
                        let value = ((word(k) << shift) as i64) >> shift;
                        u32::try_from(value).map_err(|_| {
                            bad(source, format!("label {value} is negative or too large"))
                        })
                    })
                    .collect::<Result<_>>()?,
            )
        }
        _ => {
            return Err(bad(
                source,
                format!("type `{descr}` is not read: floats or integers only"),
            ));
        }
    };
    Ok(Npy {
        rows,
        columns,
        data,
    })
}

/// The bytes of a `.npy` file (version 1) holding `values` as a `rows × columns` array of
/// little-endian `float32`.
pub fn write_npy_f32(values: &[f32], rows: usize, columns: usize) -> Vec<u8> {
    npy_bytes(
        "<f4",
        rows,
        columns,
        values.iter().flat_map(|v| v.to_le_bytes()),
    )
}

/// The bytes of a `.npy` file (version 1) holding `values` as a `rows × columns` array of
/// little-endian `uint32`: instance labels.
pub fn write_npy_u32(values: &[u32], rows: usize, columns: usize) -> Vec<u8> {
    npy_bytes(
        "<u4",
        rows,
        columns,
        values.iter().flat_map(|v| v.to_le_bytes()),
    )
}

fn npy_bytes(descr: &str, rows: usize, columns: usize, data: impl Iterator<Item = u8>) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, {columns}), }}");
    // The magic, version, length and header end on a multiple of 64 bytes, with a newline.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend(data);
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_labels_read_back() {
        let values = [0_u32, 7, 70_000, 1, 2, 3];
        let read = read_npy(&write_npy_u32(&values, 3, 2), "test").unwrap();
        assert_eq!((read.rows, read.columns), (3, 2));
        assert_eq!(read.data, NpyData::Integer(values.to_vec()));
    }

    #[test]
    fn a_written_array_reads_back() {
        let values = [0.5_f32, 1.25, f32::NAN, -2.0, 3.0, 7.5];
        let read = read_npy(&write_npy_f32(&values, 2, 3), "test").unwrap();
        assert_eq!((read.rows, read.columns), (2, 3));
        let NpyData::Float(back) = read.data else {
            panic!()
        };
        assert!(
            back.iter()
                .zip(values)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }

    #[test]
    fn integer_headers_as_numpy_writes_them_are_read() {
        // numpy.save of np.array([[1, 2], [3, 65535]], dtype='<u2').
        let header = "{'descr': '<u2', 'fortran_order': False, 'shape': (2, 2), }";
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
        bytes.extend_from_slice(header.as_bytes());
        for v in [1_u16, 2, 3, 65535] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        let read = read_npy(&bytes, "test").unwrap();
        assert_eq!(read.data, NpyData::Unsigned16(vec![1, 2, 3, 65535]));
        let cut = &bytes[..bytes.len() - 1];
        assert!(
            read_npy(cut, "test")
                .unwrap_err()
                .to_string()
                .contains("need 8 bytes")
        );
        let three = header.replace("(2, 2)", "(1, 2, 2)");
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(three.len() as u16).to_le_bytes());
        bytes.extend_from_slice(three.as_bytes());
        assert!(
            read_npy(&bytes, "test")
                .unwrap_err()
                .to_string()
                .contains("two dimensions")
        );
    }
}
