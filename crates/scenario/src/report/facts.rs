//! A report's scalar fields as named facts, read by serialising the report into a sink
//! that keeps scalars by path and passes over sequences without holding them: a report
//! with a raster of 10⁸ cells costs no more to name than one without.

use std::collections::BTreeMap;

use serde::Serialize;
use serde::ser::{self, Impossible};

use crate::outcome::Fact;

/// The scalars of `value` by path, except the top-level fields named in `skip`.
pub(super) fn of(value: &impl Serialize, skip: &[&str]) -> BTreeMap<String, Fact> {
    let mut facts = BTreeMap::new();
    // A map key that is not a string is the only way out, and no report holds one.
    let _ = value.serialize(Sink { path: String::new(), facts: &mut facts, skip });
    facts
}

/// Why the sink stopped (a key that is not text).
#[derive(Debug)]
pub(super) struct NotAFact(String);

impl std::fmt::Display for NotAFact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotAFact {}

impl ser::Error for NotAFact {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        NotAFact(msg.to_string())
    }
}

/// Receives one value at `path`.
struct Sink<'a> {
    path: String,
    facts: &'a mut BTreeMap<String, Fact>,
    /// Top-level fields passed over.
    skip: &'a [&'a str],
}

impl<'a> Sink<'a> {
    fn put(self, fact: Fact) -> Result<(), NotAFact> {
        self.facts.insert(self.path, fact);
        Ok(())
    }

    fn child<'b>(&'b mut self, name: &str) -> Sink<'b> {
        let path = if self.path.is_empty() { name.to_string() } else { format!("{}.{name}", self.path) };
        Sink { path, facts: self.facts, skip: &[] }
    }

    fn number(self, x: f64) -> Result<(), NotAFact> {
        // As JSON writes it: a value that is not finite is absent.
        if x.is_finite() { self.put(Fact::Number(x)) } else { Ok(()) }
    }

    fn signed(self, n: i64) -> Result<(), NotAFact> {
        match u64::try_from(n) {
            Ok(count) => self.put(Fact::Count(count)),
            Err(_) => self.put(Fact::Number(n as f64)),
        }
    }
}

/// A group's fields (struct, map, struct variant), each at its own path.
struct Fields<'a> {
    sink: Sink<'a>,
    key: Option<String>,
}

impl Fields<'_> {
    fn field<T: Serialize + ?Sized>(&mut self, name: &str, value: &T) -> Result<(), NotAFact> {
        if self.sink.path.is_empty() && self.sink.skip.contains(&name) {
            return Ok(());
        }
        value.serialize(self.sink.child(name))
    }
}

/// A sequence's items: not facts, passed over.
struct Items;

macro_rules! pass_over {
    ($($trait:ident :: $method:ident),*) => {$(
        impl ser::$trait for Items {
            type Ok = ();
            type Error = NotAFact;
            fn $method<T: Serialize + ?Sized>(&mut self, _: &T) -> Result<(), NotAFact> {
                Ok(())
            }
            fn end(self) -> Result<(), NotAFact> {
                Ok(())
            }
        }
    )*};
}
pass_over!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field,
    SerializeTupleVariant::serialize_field
);

impl ser::SerializeStruct for Fields<'_> {
    type Ok = ();
    type Error = NotAFact;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> Result<(), NotAFact> {
        self.field(key, value)
    }
    fn end(self) -> Result<(), NotAFact> {
        Ok(())
    }
}

impl ser::SerializeStructVariant for Fields<'_> {
    type Ok = ();
    type Error = NotAFact;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> Result<(), NotAFact> {
        self.field(key, value)
    }
    fn end(self) -> Result<(), NotAFact> {
        Ok(())
    }
}

impl ser::SerializeMap for Fields<'_> {
    type Ok = ();
    type Error = NotAFact;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), NotAFact> {
        self.key = Some(key.serialize(KeyText)?);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), NotAFact> {
        let key = self.key.take().ok_or_else(|| NotAFact("a map value without its key".into()))?;
        self.field(&key, value)
    }
    fn end(self) -> Result<(), NotAFact> {
        Ok(())
    }
}

impl<'a> ser::Serializer for Sink<'a> {
    type Ok = ();
    type Error = NotAFact;
    type SerializeSeq = Items;
    type SerializeTuple = Items;
    type SerializeTupleStruct = Items;
    type SerializeTupleVariant = Items;
    type SerializeMap = Fields<'a>;
    type SerializeStruct = Fields<'a>;
    type SerializeStructVariant = Fields<'a>;

    fn serialize_bool(self, v: bool) -> Result<(), NotAFact> {
        self.put(Fact::Flag(v))
    }
    fn serialize_i8(self, v: i8) -> Result<(), NotAFact> {
        self.signed(v.into())
    }
    fn serialize_i16(self, v: i16) -> Result<(), NotAFact> {
        self.signed(v.into())
    }
    fn serialize_i32(self, v: i32) -> Result<(), NotAFact> {
        self.signed(v.into())
    }
    fn serialize_i64(self, v: i64) -> Result<(), NotAFact> {
        self.signed(v)
    }
    fn serialize_u8(self, v: u8) -> Result<(), NotAFact> {
        self.put(Fact::Count(v.into()))
    }
    fn serialize_u16(self, v: u16) -> Result<(), NotAFact> {
        self.put(Fact::Count(v.into()))
    }
    fn serialize_u32(self, v: u32) -> Result<(), NotAFact> {
        self.put(Fact::Count(v.into()))
    }
    fn serialize_u64(self, v: u64) -> Result<(), NotAFact> {
        self.put(Fact::Count(v))
    }
    fn serialize_f32(self, v: f32) -> Result<(), NotAFact> {
        self.number(v.into())
    }
    fn serialize_f64(self, v: f64) -> Result<(), NotAFact> {
        self.number(v)
    }
    fn serialize_char(self, v: char) -> Result<(), NotAFact> {
        self.put(Fact::Text(v.to_string()))
    }
    fn serialize_str(self, v: &str) -> Result<(), NotAFact> {
        self.put(Fact::Text(v.to_string()))
    }
    fn serialize_bytes(self, _: &[u8]) -> Result<(), NotAFact> {
        Ok(())
    }
    fn serialize_none(self) -> Result<(), NotAFact> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<(), NotAFact> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), NotAFact> {
        Ok(())
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<(), NotAFact> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, variant: &'static str) -> Result<(), NotAFact> {
        self.put(Fact::Text(variant.to_string()))
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, _: &'static str, value: &T) -> Result<(), NotAFact> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        mut self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        value: &T,
    ) -> Result<(), NotAFact> {
        value.serialize(self.child(variant))
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Items, NotAFact> {
        Ok(Items)
    }
    fn serialize_tuple(self, _: usize) -> Result<Items, NotAFact> {
        Ok(Items)
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Items, NotAFact> {
        Ok(Items)
    }
    fn serialize_tuple_variant(self, _: &'static str, _: u32, _: &'static str, _: usize) -> Result<Items, NotAFact> {
        Ok(Items)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Fields<'a>, NotAFact> {
        Ok(Fields { sink: self, key: None })
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Fields<'a>, NotAFact> {
        Ok(Fields { sink: self, key: None })
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Fields<'a>, NotAFact> {
        let path = if self.path.is_empty() { variant.to_string() } else { format!("{}.{variant}", self.path) };
        Ok(Fields { sink: Sink { path, facts: self.facts, skip: &[] }, key: None })
    }
}

/// A map key as text (a number or a unit variant written as JSON would key it).
struct KeyText;

macro_rules! key_from_display {
    ($($method:ident: $t:ty),*) => {$(
        fn $method(self, v: $t) -> Result<String, NotAFact> {
            Ok(v.to_string())
        }
    )*};
}

impl ser::Serializer for KeyText {
    type Ok = String;
    type Error = NotAFact;
    type SerializeSeq = Impossible<String, NotAFact>;
    type SerializeTuple = Impossible<String, NotAFact>;
    type SerializeTupleStruct = Impossible<String, NotAFact>;
    type SerializeTupleVariant = Impossible<String, NotAFact>;
    type SerializeMap = Impossible<String, NotAFact>;
    type SerializeStruct = Impossible<String, NotAFact>;
    type SerializeStructVariant = Impossible<String, NotAFact>;

    key_from_display!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32, serialize_i64: i64,
        serialize_u8: u8, serialize_u16: u16, serialize_u32: u32, serialize_u64: u64, serialize_f32: f32,
        serialize_f64: f64, serialize_char: char, serialize_str: &str);

    fn serialize_bytes(self, _: &[u8]) -> Result<String, NotAFact> {
        Err(NotAFact("a map key of bytes".into()))
    }
    fn serialize_none(self) -> Result<String, NotAFact> {
        Err(NotAFact("an absent map key".into()))
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<String, NotAFact> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<String, NotAFact> {
        Err(NotAFact("a unit map key".into()))
    }
    fn serialize_unit_struct(self, name: &'static str) -> Result<String, NotAFact> {
        Ok(name.to_string())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, variant: &'static str) -> Result<String, NotAFact> {
        Ok(variant.to_string())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, _: &'static str, value: &T) -> Result<String, NotAFact> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<String, NotAFact> {
        Err(NotAFact("a map key that is an enum with data".into()))
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotAFact> {
        Err(NotAFact("a map key that is a sequence".into()))
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, NotAFact> {
        Err(NotAFact("a map key that is a tuple".into()))
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self::SerializeTupleStruct, NotAFact> {
        Err(NotAFact("a map key that is a tuple".into()))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotAFact> {
        Err(NotAFact("a map key that is a tuple".into()))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotAFact> {
        Err(NotAFact("a map key that is a map".into()))
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self::SerializeStruct, NotAFact> {
        Err(NotAFact("a map key that is a struct".into()))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotAFact> {
        Err(NotAFact("a map key that is a struct".into()))
    }
}
