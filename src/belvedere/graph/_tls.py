"""TLS for a graph open to other hosts (``--listen tls/IP:PORT``), with certificates that
every holder of the graph's token makes alike and no file has to be copied between hosts.

The token seeds (HKDF-SHA256) two Ed25519 keys: a certificate authority's and the graph's.
Ed25519 signatures are deterministic, so each host builds byte-identical certificates: a
listener presents the graph's certificate, and a connecting host trusts only that authority.
A host without the token can neither present nor verify them, so the TLS handshake fails
before Zenoh's own token check; with it, the traffic is encrypted. Whoever holds the token
can act as the graph, as whoever holds a shared password can.
"""

from __future__ import annotations

import atexit
import datetime
import os
import shutil
import tempfile
from typing import Any, Final

__all__ = ["tls_settings"]

_SERVER_NAME: Final = "belvedere-graph"
# fixed validity and serials: the certificates must be identical on every host
_NOT_BEFORE: Final = datetime.datetime(2024, 1, 1, tzinfo=datetime.UTC)
_NOT_AFTER: Final = datetime.datetime(2124, 1, 1, tzinfo=datetime.UTC)

_made: dict[str, dict[str, Any]] = {}


def _key(token: str, label: str) -> Any:
    from cryptography.hazmat.primitives import hashes
    from cryptography.hazmat.primitives.asymmetric import ed25519
    from cryptography.hazmat.primitives.kdf.hkdf import HKDF

    seed = HKDF(
        algorithm=hashes.SHA256(), length=32, salt=b"belvedere graph tls", info=label.encode()
    ).derive(token.encode())
    return ed25519.Ed25519PrivateKey.from_private_bytes(seed)


def _certificates(token: str) -> tuple[bytes, bytes, bytes]:
    """(authority's certificate, graph's certificate, graph's private key), as PEM."""
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization
    from cryptography.x509.oid import NameOID

    ca_key, graph_key = _key(token, "authority"), _key(token, "graph")
    ca_name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "belvedere graph authority")])
    usage = {
        "digital_signature": True,
        "content_commitment": False,
        "key_encipherment": False,
        "data_encipherment": False,
        "key_agreement": False,
        "encipher_only": False,
        "decipher_only": False,
    }
    ca = (
        x509.CertificateBuilder()
        .subject_name(ca_name)
        .issuer_name(ca_name)
        .public_key(ca_key.public_key())
        .serial_number(1)
        .not_valid_before(_NOT_BEFORE)
        .not_valid_after(_NOT_AFTER)
        .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        .add_extension(x509.KeyUsage(**usage, key_cert_sign=True, crl_sign=True), critical=True)
        .sign(ca_key, None)
    )
    graph = (
        x509.CertificateBuilder()
        .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, _SERVER_NAME)]))
        .issuer_name(ca_name)
        .public_key(graph_key.public_key())
        .serial_number(2)
        .not_valid_before(_NOT_BEFORE)
        .not_valid_after(_NOT_AFTER)
        .add_extension(x509.SubjectAlternativeName([x509.DNSName(_SERVER_NAME)]), critical=False)
        .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
        .sign(ca_key, None)
    )
    pem = serialization.Encoding.PEM
    key = graph_key.private_bytes(
        pem, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )
    return ca.public_bytes(pem), graph.public_bytes(pem), key


def tls_settings(token: str) -> dict[str, Any]:
    """Zenoh's ``transport/link/tls`` settings for the graph of ``token``: its files are
    written once per process, in a folder only this user can read, and removed at exit."""
    settings = _made.get(token)
    if settings is not None:
        return settings
    folder = tempfile.mkdtemp(prefix="belvedere-graph-tls-")  # mode 0700
    files = {}
    for name, data in zip(("ca.pem", "graph.pem", "graph.key"), _certificates(token), strict=True):
        path = os.path.join(folder, name)
        with open(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600), "wb") as out:
            out.write(data)
        files[name] = path
    settings = {
        "root_ca_certificate": files["ca.pem"],
        "listen_certificate": files["graph.pem"],
        "listen_private_key": files["graph.key"],
        # hosts are reached by any address or name: the authority, not the name, is checked
        "verify_name_on_connect": False,
    }
    _made[token] = settings
    atexit.register(shutil.rmtree, folder, True)
    return settings
