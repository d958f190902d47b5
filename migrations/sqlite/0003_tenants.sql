-- Ownership: the name of the API token that created a job or study ('' when the service
-- runs without tokens). Listings are scoped by it; idempotency and scene keys carry it.
ALTER TABLE jobs ADD COLUMN tenant TEXT NOT NULL DEFAULT '';
ALTER TABLE studies ADD COLUMN tenant TEXT NOT NULL DEFAULT '';
CREATE INDEX jobs_tenant_seq ON jobs (tenant, seq);
CREATE INDEX studies_tenant_seq ON studies (tenant, seq);
