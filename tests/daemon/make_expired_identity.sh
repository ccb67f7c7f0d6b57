#!/usr/bin/env bash
# For the DDS Security tests: PKI/expired, a copy of PKI/station whose certificate (same key, same
# CA) was valid for one day in 2020. openssl 3.0's `x509 -req` cannot back-date, so `openssl ca`
# signs it with explicit dates.
# Usage: tests/daemon/make_expired_identity.sh PKI   (PKI made by scripts/make-pki.sh)
set -euo pipefail
pki=${1:?usage: make_expired_identity.sh PKI}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/new" "$pki/expired"
touch "$work/index.txt"
echo 1000 > "$work/serial"
cat > "$work/ca.cnf" << EOF
[ ca ]
default_ca = expired_ca
[ expired_ca ]
database = $work/index.txt
new_certs_dir = $work/new
serial = $work/serial
default_md = sha256
policy = any_name
[ any_name ]
organizationName = optional
commonName = supplied
EOF
cp "$pki/station/"* "$pki/expired/"
openssl req -new -key "$pki/station/identity.key" -subj "/O=skyroute/CN=skyroute expired" -out "$work/expired.csr" 2> /dev/null
openssl ca -batch -config "$work/ca.cnf" -cert "$pki/ca/ca.pem" -keyfile "$pki/ca/ca.key" -in "$work/expired.csr" \
  -out "$pki/expired/identity.pem" -startdate 20200101000000Z -enddate 20200102000000Z -notext 2> /dev/null
