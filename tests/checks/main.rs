//! Checks of the sources and documents, no service running: the import graph and layer
//! table, the committed OpenAPI document, the stored inputs' format number, and the
//! engine paths the docs name.

mod docs_paths;
mod import_graph;
mod input_format;
mod openapi;
