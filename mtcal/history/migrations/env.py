"""Alembic environment of the history store (mtcal.history.store runs it programmatically on the store's own
connection, inside the store's transaction: a migration is all or nothing)."""
from alembic import context

connection = context.config.attributes["connection"]
context.configure(connection=connection, target_metadata=None, transactional_ddl=True,
                  render_as_batch=connection.dialect.name == "sqlite")
with context.begin_transaction():
    context.run_migrations()
