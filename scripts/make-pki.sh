#!/usr/bin/env bash
# Makes the keys and signed documents of a DDS Security deployment (docs/dds.md, "DDS Security"):
# one CA that signs the identities and the permissions, the governance (authentication required,
# discovery, liveliness and data encrypted), the permissions, and one folder per identity holding
# everything that program needs, to pass as `--security DIR`:
#   DIR/daemon/    skyrouted: writes every topic (trajectories, statuses, heartbeats), reads all
#   DIR/station/   a ground station: writes missions, fleet requests, cancels and obstacle updates
#   DIR/observer/  reads every topic and writes none
# Each folder holds identity_ca.pem, identity.pem, identity.key, permissions_ca.pem,
# governance.p7s and permissions.p7s. The CA's key stays in DIR/ca/ (keep it off the vehicles).
#
# Usage: scripts/make-pki.sh DIR [--days N] [--domains MIN-MAX] [--cn-prefix TEXT] [--reuse-ca]
#   --days N         validity of the certificates and permissions (default 365)
#   --domains A-B    DDS domain ids the governance and permissions cover (default 0-230: Cyclone
#                    0.10's parser of these documents refuses ids above 230)
#   --cn-prefix T    prefix of the identities' common names (default "skyroute"), so two
#                    deployments' certificates differ
#   --reuse-ca       keep DIR/ca/ca.key and ca.pem when they exist (renewing the identities)
# Renewing: run again into a new DIR with the same CA (--reuse-ca) and roll the folders out;
# rotating the CA: a new DIR without --reuse-ca, rolled out to every program at once.
set -euo pipefail

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
dir=$1
shift
days=365
domains=0-230
prefix=skyroute
reuse_ca=0
while [ $# -gt 0 ]; do
  case "$1" in
    --days) days=${2:?--days needs a number}; shift 2 ;;
    --domains) domains=${2:?--domains needs MIN-MAX}; shift 2 ;;
    --cn-prefix) prefix=${2:?--cn-prefix needs text}; shift 2 ;;
    --reuse-ca) reuse_ca=1; shift ;;
    *) echo "make-pki: unknown option $1" >&2; usage ;;
  esac
done
[[ $days =~ ^[0-9]+$ && $days -ge 1 ]] || { echo "make-pki: --days must be a positive integer" >&2; exit 2; }
[[ $domains =~ ^([0-9]+)-([0-9]+)$ ]] || { echo "make-pki: --domains must be MIN-MAX" >&2; exit 2; }
domain_min=${BASH_REMATCH[1]}
domain_max=${BASH_REMATCH[2]}
(( domain_min <= domain_max && domain_max <= 230 )) || { echo "make-pki: --domains must be MIN-MAX with MIN <= MAX <= 230" >&2; exit 2; }
[[ $prefix =~ ^[A-Za-z0-9._-]+$ ]] || { echo "make-pki: --cn-prefix: letters, digits, '.', '_' and '-' only" >&2; exit 2; }
command -v openssl > /dev/null || { echo "make-pki: needs openssl (apt-get install openssl)" >&2; exit 1; }

umask 077
mkdir -p "$dir/ca"
ca_key=$dir/ca/ca.key
ca_pem=$dir/ca/ca.pem
if [ "$reuse_ca" -eq 0 ] || [ ! -f "$ca_key" ]; then
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -sha256 -days "$days" \
    -subj "/O=$prefix/CN=$prefix CA" -keyout "$ca_key" -out "$ca_pem" 2> /dev/null
fi

# Governance: nobody joins without authenticating; discovery, liveliness, metadata and data are
# encrypted on every topic; reading and writing are access-controlled.
cat > "$dir/ca/governance.xml" << EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>$domain_min</min><max>$domain_max</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF

# One identity: a key and a certificate signed by the CA; prints its subject as the permissions
# name it.
identity() {
  local name=$1
  local out=$dir/$name
  mkdir -p "$out"
  openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -sha256 \
    -subj "/O=$prefix/CN=$prefix $name" -keyout "$out/identity.key" -out "$out/identity.csr" 2> /dev/null
  openssl x509 -req -in "$out/identity.csr" -CA "$ca_pem" -CAkey "$ca_key" -CAcreateserial -sha256 \
    -days "$days" -out "$out/identity.pem" 2> /dev/null
  rm -f "$out/identity.csr"
  openssl x509 -noout -subject -nameopt RFC2253 -in "$out/identity.pem" | sed 's/^subject=//'
}

# A grant: what one subject may publish (topic names, or * for all); everyone granted reads all.
grant() {
  local name=$1 subject=$2
  shift 2
  local not_before not_after
  not_before=$(date -u +%Y-%m-%dT%H:%M:%S -d '1 hour ago')
  not_after=$(date -u +%Y-%m-%dT%H:%M:%S -d "$days days")
  echo "    <grant name=\"$name\">"
  echo "      <subject_name>$subject</subject_name>"
  echo "      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>"
  echo "      <allow_rule>"
  echo "        <domains><id_range><min>$domain_min</min><max>$domain_max</max></id_range></domains>"
  if [ $# -gt 0 ]; then
    echo "        <publish><topics>"
    for topic in "$@"; do echo "          <topic>$topic</topic>"; done
    echo "        </topics></publish>"
  fi
  echo "        <subscribe><topics><topic>*</topic></topics></subscribe>"
  echo "      </allow_rule>"
  echo "      <default>DENY</default>"
  echo "    </grant>"
}

daemon_subject=$(identity daemon)
station_subject=$(identity station)
observer_subject=$(identity observer)
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  echo '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"'
  echo '     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">'
  echo '  <permissions>'
  grant daemon "$daemon_subject" '*'
  grant station "$station_subject" skyroute_mission_request skyroute_cancel_request skyroute_obstacle_update \
    skyroute_fleet_request skyroute_no_fly_zone
  grant observer "$observer_subject"
  echo '  </permissions>'
  echo '</dds>'
} > "$dir/ca/permissions.xml"

for doc in governance permissions; do
  openssl smime -sign -text -in "$dir/ca/$doc.xml" -out "$dir/ca/$doc.p7s" -signer "$ca_pem" -inkey "$ca_key" 2> /dev/null
done
for name in daemon station observer; do
  cp "$ca_pem" "$dir/$name/identity_ca.pem"
  cp "$ca_pem" "$dir/$name/permissions_ca.pem"
  cp "$dir/ca/governance.p7s" "$dir/ca/permissions.p7s" "$dir/$name/"
done
echo "make-pki: $dir/daemon, $dir/station and $dir/observer (valid $days days, domains $domain_min-$domain_max)"
