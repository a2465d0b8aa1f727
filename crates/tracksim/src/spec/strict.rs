//! Strict shapes: a second pass over a parsed TOML document that rejects what serde's derived
//! code would otherwise accept silently: a table written as an array (`ground = [0.6, -0.5]`
//! read by position) and a fixed-size array with extra entries (`size_m = [0.5, 3, 0.1, 99]`
//! read as its first three). The first pass (`toml::from_str`) reports types and unknown keys
//! with line and column; this one names the key path, as the compile checks do.

use serde::de::{self, DeserializeOwned, IntoDeserializer, Visitor};

/// A strict-pass problem: the key path and what is wrong.
#[derive(Debug)]
pub struct StrictError(pub String, bool);

impl StrictError {
    fn at(message: String) -> Self {
        StrictError(message, true)
    }
    /// Prefixes `path` to a message serde made without one (inside a tagged enum).
    fn locate(self, path: &str) -> Self {
        if self.1 {
            self
        } else {
            StrictError(format!("{path}: {}", self.0), true)
        }
    }
}

impl std::fmt::Display for StrictError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for StrictError {}

impl de::Error for StrictError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        StrictError(msg.to_string(), false)
    }
}

/// Deserializes `T` from `value` strictly; the error message starts with the key path.
pub fn from_value<T: DeserializeOwned>(value: &toml::Value) -> Result<T, StrictError> {
    T::deserialize(Strict {
        value,
        path: String::new(),
    })
}

/// One value and its key path.
struct Strict<'a> {
    value: &'a toml::Value,
    path: String,
}

impl<'a> Strict<'a> {
    fn child_key(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }
    fn err(&self, message: String) -> StrictError {
        let at = if self.path.is_empty() {
            "the file"
        } else {
            &self.path
        };
        StrictError::at(format!("{at}: {message}"))
    }
    fn what(&self) -> &'static str {
        match self.value {
            toml::Value::String(_) => "a string",
            toml::Value::Integer(_) => "an integer",
            toml::Value::Float(_) => "a number",
            toml::Value::Boolean(_) => "a boolean",
            toml::Value::Datetime(_) => "a date",
            toml::Value::Array(_) => "an array",
            toml::Value::Table(_) => "a table",
        }
    }
}

struct Seq<'a> {
    items: std::iter::Enumerate<std::slice::Iter<'a, toml::Value>>,
    path: String,
}

impl<'de, 'a> de::SeqAccess<'de> for Seq<'a> {
    type Error = StrictError;
    fn next_element_seed<S: de::DeserializeSeed<'de>>(
        &mut self,
        seed: S,
    ) -> Result<Option<S::Value>, StrictError> {
        match self.items.next() {
            None => Ok(None),
            Some((i, value)) => {
                let path = format!("{}[{i}]", self.path);
                seed.deserialize(Strict {
                    value,
                    path: path.clone(),
                })
                .map(Some)
                .map_err(|e| e.locate(&path))
            }
        }
    }
    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len())
    }
}

struct Map<'a> {
    entries: toml::map::Iter<'a, String, toml::Value>,
    pending: Option<(&'a String, &'a toml::Value)>,
    path: String,
}

impl<'de, 'a> de::MapAccess<'de> for Map<'a> {
    type Error = StrictError;
    fn next_key_seed<K: de::DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, StrictError> {
        match self.entries.next() {
            None => Ok(None),
            Some((k, v)) => {
                self.pending = Some((k, v));
                seed.deserialize(k.as_str().into_deserializer()).map(Some)
            }
        }
    }
    fn next_value_seed<V: de::DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, StrictError> {
        let (k, value) = self
            .pending
            .take()
            .ok_or_else(|| StrictError::at("a value without a key".into()))?;
        let s = Strict {
            value,
            path: self.path.clone(),
        };
        let path = s.child_key(k);
        seed.deserialize(Strict {
            value,
            path: path.clone(),
        })
        .map_err(|e| e.locate(&path))
    }
}

struct Enum<'a> {
    variant: &'a str,
    value: Option<&'a toml::Value>,
    path: String,
}

impl<'de, 'a> de::EnumAccess<'de> for Enum<'a> {
    type Error = StrictError;
    type Variant = Self;
    fn variant_seed<V: de::DeserializeSeed<'de>>(
        self,
        seed: V,
    ) -> Result<(V::Value, Self), StrictError> {
        let v = seed.deserialize(self.variant.into_deserializer())?;
        Ok((v, self))
    }
}

impl<'de, 'a> de::VariantAccess<'de> for Enum<'a> {
    type Error = StrictError;
    fn unit_variant(self) -> Result<(), StrictError> {
        Ok(())
    }
    fn newtype_variant_seed<T: de::DeserializeSeed<'de>>(
        self,
        seed: T,
    ) -> Result<T::Value, StrictError> {
        let value = self
            .value
            .ok_or_else(|| StrictError::at(format!("{}: expected a value", self.path)))?;
        seed.deserialize(Strict {
            value,
            path: self.path,
        })
    }
    fn tuple_variant<V: Visitor<'de>>(
        self,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        let value = self
            .value
            .ok_or_else(|| StrictError::at(format!("{}: expected an array", self.path)))?;
        de::Deserializer::deserialize_tuple(
            Strict {
                value,
                path: self.path,
            },
            len,
            visitor,
        )
    }
    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        let value = self
            .value
            .ok_or_else(|| StrictError::at(format!("{}: expected a table", self.path)))?;
        de::Deserializer::deserialize_struct(
            Strict {
                value,
                path: self.path,
            },
            "",
            fields,
            visitor,
        )
    }
}

impl<'de, 'a> de::Deserializer<'de> for Strict<'a> {
    type Error = StrictError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, StrictError> {
        match self.value {
            toml::Value::String(s) => visitor.visit_str(s),
            toml::Value::Integer(i) => visitor.visit_i64(*i),
            toml::Value::Float(x) => visitor.visit_f64(*x),
            toml::Value::Boolean(b) => visitor.visit_bool(*b),
            toml::Value::Datetime(d) => visitor.visit_string(d.to_string()),
            toml::Value::Array(a) => visitor.visit_seq(Seq {
                items: a.iter().enumerate(),
                path: self.path,
            }),
            toml::Value::Table(t) => visitor.visit_map(Map {
                entries: t.iter(),
                pending: None,
                path: self.path,
            }),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, StrictError> {
        visitor.visit_some(self)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        self.deserialize_map(visitor)
    }

    fn deserialize_map<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, StrictError> {
        match self.value {
            toml::Value::Table(_) => self.deserialize_any(visitor),
            _ => Err(self.err(format!(
                "must be a table (`key = value` entries, e.g. `{{ friction = 0.6 }}`), got {}; \
                 an array is not read by position",
                self.what()
            ))),
        }
    }

    fn deserialize_tuple<V: Visitor<'de>>(
        self,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        match self.value {
            toml::Value::Array(a) if a.len() != len => {
                Err(self.err(format!("must have exactly {len} entries, got {}", a.len())))
            }
            _ => self.deserialize_any(visitor),
        }
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        self.deserialize_tuple(len, visitor)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        match self.value {
            toml::Value::String(s) => visitor.visit_enum(Enum {
                variant: s,
                value: None,
                path: self.path,
            }),
            toml::Value::Table(t) if t.len() == 1 => {
                let (k, v) = t.iter().next().expect("one entry");
                let path = self.child_key(k);
                visitor.visit_enum(Enum {
                    variant: k,
                    value: Some(v),
                    path,
                })
            }
            _ => Err(self.err(format!("must be a name (a string), got {}", self.what()))),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf unit unit_struct seq identifier ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{ScenarioSpec, VehicleSpec};

    fn strict<T: DeserializeOwned>(text: &str) -> Result<T, String> {
        let v: toml::Value = toml::Value::Table(toml::from_str(text).map_err(|e| format!("{e}"))?);
        from_value(&v).map_err(|e| e.0)
    }

    #[test]
    fn every_bundled_file_reads_as_the_first_pass_reads_it() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let mut n = 0;
        for dir in [
            "vehicles",
            "scenarios",
            "scenarios/random",
            "scenarios/classic",
        ] {
            let Ok(rd) = std::fs::read_dir(root.join(dir)) else {
                continue;
            };
            for e in rd {
                let p = e.unwrap().path();
                if p.extension().is_none_or(|x| x != "toml") {
                    continue;
                }
                let text = std::fs::read_to_string(&p).unwrap();
                if dir == "vehicles" {
                    let a: VehicleSpec = toml::from_str(&text).unwrap();
                    let b: VehicleSpec = strict(&text).unwrap();
                    assert_eq!(format!("{a:?}"), format!("{b:?}"), "{}", p.display());
                } else {
                    let a: ScenarioSpec = toml::from_str(&text).unwrap();
                    let b: ScenarioSpec = strict(&text).unwrap();
                    assert_eq!(format!("{a:?}"), format!("{b:?}"), "{}", p.display());
                }
                n += 1;
            }
        }
        assert!(n > 15, "only {n} bundled files found");
    }

    #[test]
    fn tables_as_arrays_and_long_arrays_are_named() {
        let base = "[vehicle]\nfile = \"v.toml\"\n";
        let e = strict::<ScenarioSpec>(&format!("{base}[terrain]\nground = [0.6, -0.5]\n"))
            .unwrap_err();
        assert!(e.starts_with("terrain.ground: must be a table"), "{e}");
        let e = strict::<ScenarioSpec>(&format!(
            "{base}[[terrain.boxes]]\ncentre_m = [0, 0, 0]\nsize_m = [0.5, 3.0, 0.1, 99.0]\n"
        ))
        .unwrap_err();
        assert!(
            e.starts_with("terrain.boxes[0].size_m: must have exactly 3 entries, got 4"),
            "{e}"
        );
    }
}
