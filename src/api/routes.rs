//! The single route table: the router is built from it and a test checks that the
//! generated OpenAPI document has exactly these paths and methods.

use super::state::AppState;
use super::{
    analyses, ops, presets, quasi_static, recordings, simulation_plots, simulation_recording,
    simulations, studies,
};
use axum::handler::Handler;
use axum::routing::{on, MethodFilter, MethodRouter};

pub struct RouteDef {
    #[cfg_attr(not(test), allow(dead_code))]
    pub method: &'static str,
    pub path: &'static str,
    /// Exempt from the request timeout (it may wait on purpose).
    pub long_poll: bool,
    pub handler: MethodRouter<AppState>,
}

/// The method string both filters the handler and names the operation in the spec test.
fn r<H: Handler<T, AppState>, T: 'static>(
    method: &'static str,
    path: &'static str,
    handler: H,
) -> RouteDef {
    let filter = match method {
        "get" => MethodFilter::GET,
        "post" => MethodFilter::POST,
        "delete" => MethodFilter::DELETE,
        other => panic!("route table: unsupported method {other}"),
    };
    RouteDef {
        method,
        path,
        long_poll: false,
        handler: on(filter, handler),
    }
}

pub fn table() -> Vec<RouteDef> {
    vec![
        r("post", "/v1/simulations", simulations::submit),
        r("get", "/v1/simulations", simulations::list),
        RouteDef {
            long_poll: true,
            ..r("get", "/v1/simulations/{id}", simulations::get)
        },
        r("delete", "/v1/simulations/{id}", simulations::delete),
        r("post", "/v1/simulations/{id}/cancel", simulations::cancel),
        r("get", "/v1/simulations/{id}/result", simulations::result),
        r("get", "/v1/simulations/{id}/signals", simulations::signals),
        r(
            "get",
            "/v1/simulations/{id}/recording",
            simulation_recording::recording,
        ),
        r("get", "/v1/simulations/{id}/spectra", simulations::spectra),
        r(
            "get",
            "/v1/simulations/{id}/plots/{name}",
            simulation_plots::plot,
        ),
        r("post", "/v1/studies", studies::submit),
        r("get", "/v1/studies", studies::list),
        RouteDef {
            long_poll: true,
            ..r("get", "/v1/studies/{id}", studies::get)
        },
        r("delete", "/v1/studies/{id}", studies::delete),
        r("post", "/v1/studies/{id}/cancel", studies::cancel),
        r("get", "/v1/studies/{id}/table", studies::table),
        r("get", "/v1/studies/{id}/plots/{name}", studies::plot),
        r("post", "/v1/analyses", analyses::submit),
        r("post", "/v1/recordings/inspect", recordings::inspect),
        r("get", "/v1/analyses", analyses::list),
        RouteDef {
            long_poll: true,
            ..r("get", "/v1/analyses/{id}", analyses::get)
        },
        r("delete", "/v1/analyses/{id}", analyses::delete),
        r("post", "/v1/analyses/{id}/cancel", analyses::cancel),
        r("get", "/v1/analyses/{id}/result", analyses::result),
        r("get", "/v1/analyses/{id}/spectra", analyses::spectra),
        r("post", "/v1/quasi-static", quasi_static::solve),
        r("get", "/v1/presets", presets::list),
        r("get", "/v1/presets/{name}", presets::get),
        r("get", "/healthz", ops::healthz),
        r("get", "/readyz", ops::readyz),
        r("get", "/metrics", ops::metrics),
        r("get", "/openapi.yaml", ops::openapi),
    ]
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    #[test]
    fn the_document_has_exactly_the_routes() {
        let routes: BTreeSet<(String, String)> = super::table()
            .iter()
            .map(|r| (r.method.to_string(), r.path.to_string()))
            .collect();
        let doc = crate::api::openapi::document();
        let mut documented = BTreeSet::new();
        for (path, item) in &doc.paths.paths {
            for (method, op) in [
                ("get", &item.get),
                ("post", &item.post),
                ("delete", &item.delete),
                ("put", &item.put),
                ("patch", &item.patch),
            ] {
                if op.is_some() {
                    documented.insert((method.to_string(), path.clone()));
                }
            }
        }
        let undocumented: Vec<_> = routes.difference(&documented).collect();
        let phantom: Vec<_> = documented.difference(&routes).collect();
        assert!(
            undocumented.is_empty(),
            "routes without #[utoipa::path]: {undocumented:?}"
        );
        assert!(
            phantom.is_empty(),
            "documented routes the router lacks: {phantom:?}"
        );
    }
}
