//! Running a statement on either sqlx driver from generic code.
//!
//! sqlx states what a driver can bind and run as bounds on foreign types (`i64: Encode<DB>`,
//! `&mut DB::Connection: Executor`). Rust does not carry such bounds from a trait to its
//! users, so written as bounds every shared function would repeat them. Here they are
//! stated once, on the blanket impl of [`Statements`]; the shared code only asks for a
//! [`super::Backend`] and binds [`Param`]s.

use sqlx::postgres::PgQueryResult;
use sqlx::query::Query;
use sqlx::sqlite::SqliteQueryResult;
use sqlx::{Database, Encode, Executor, Pool, Type};
use std::borrow::Cow;

/// A value bound to a statement: the few kinds the store writes, each possibly NULL.
pub enum Param<'q> {
    Text(Option<Cow<'q, str>>),
    Int(Option<i64>),
    Real(Option<f64>),
    Bytes(Option<&'q [u8]>),
}

/// `From` a value (or an `Option` of it, for NULL) of each kind bound.
macro_rules! param_from {
    ($($t:ty => |$v:ident| $param:expr;)*) => {
        $(impl<'q> From<$t> for Param<'q> {
            fn from($v: $t) -> Self {
                $param
            }
        })*
    };
}

param_from! {
    &'q str => |v| Param::Text(Some(Cow::Borrowed(v)));
    &'q String => |v| Param::Text(Some(Cow::Borrowed(v)));
    String => |v| Param::Text(Some(Cow::Owned(v)));
    Option<&'q str> => |v| Param::Text(v.map(Cow::Borrowed));
    Option<String> => |v| Param::Text(v.map(Cow::Owned));
    i64 => |v| Param::Int(Some(v));
    Option<i64> => |v| Param::Int(v);
    f64 => |v| Param::Real(Some(v));
    Option<f64> => |v| Param::Real(v);
    &'q [u8] => |v| Param::Bytes(Some(v));
    Option<&'q [u8]> => |v| Param::Bytes(v);
}

/// A sqlx statement on `DB` with its arguments.
pub type Statement<'q, DB> = Query<'q, DB, <DB as Database>::Arguments<'q>>;

/// What the shared statements need of a sqlx driver: binding a [`Param`], and running on a
/// connection (a transaction's) or on the pool. Every driver sqlx gives these has it.
pub trait Statements: Database {
    fn bind_param<'q>(statement: Statement<'q, Self>, value: Param<'q>) -> Statement<'q, Self>;

    /// A connection (`&mut *tx` of a transaction) as what statements run on.
    fn on<'c>(connection: &'c mut Self::Connection) -> impl Executor<'c, Database = Self>;

    /// The pool as what statements run on: each takes a connection for itself.
    fn on_pool(pool: &Pool<Self>) -> impl Executor<'_, Database = Self>;
}

impl<DB: Database> Statements for DB
where
    for<'q> Option<Cow<'q, str>>: Encode<'q, DB> + Type<DB>,
    for<'q> Option<i64>: Encode<'q, DB> + Type<DB>,
    for<'q> Option<f64>: Encode<'q, DB> + Type<DB>,
    for<'q> Option<&'q [u8]>: Encode<'q, DB> + Type<DB>,
    for<'c> &'c mut DB::Connection: Executor<'c, Database = DB>,
{
    fn bind_param<'q>(statement: Statement<'q, Self>, value: Param<'q>) -> Statement<'q, Self> {
        match value {
            Param::Text(v) => statement.bind(v),
            Param::Int(v) => statement.bind(v),
            Param::Real(v) => statement.bind(v),
            Param::Bytes(v) => statement.bind(v),
        }
    }

    fn on<'c>(connection: &'c mut Self::Connection) -> impl Executor<'c, Database = Self> {
        connection
    }

    fn on_pool(pool: &Pool<Self>) -> impl Executor<'_, Database = Self> {
        pool
    }
}

/// `.param(value)`: sqlx's `.bind(value)` for a [`Param`] on any [`Statements`] driver.
pub trait BindParam<'q> {
    fn param(self, value: impl Into<Param<'q>>) -> Self;
}

impl<'q, DB: Statements> BindParam<'q> for Statement<'q, DB> {
    fn param(self, value: impl Into<Param<'q>>) -> Self {
        DB::bind_param(self, value.into())
    }
}

/// How many rows a write touched (each driver has its own result type).
pub trait RowsAffected {
    fn rows_affected(&self) -> u64;
}

impl RowsAffected for SqliteQueryResult {
    fn rows_affected(&self) -> u64 {
        SqliteQueryResult::rows_affected(self)
    }
}

impl RowsAffected for PgQueryResult {
    fn rows_affected(&self) -> u64 {
        PgQueryResult::rows_affected(self)
    }
}
